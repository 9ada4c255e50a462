# Installation of flexref as a C++ package (docs/external.md, "C++"):
#   <prefix>/include/flexref/<folder>/*.hpp   the public headers of the libraries
#   <prefix>/lib/libflexref_<folder>.a        the libraries
#   <prefix>/lib/cmake/flexref/               flexrefConfig.cmake: find_package(flexref) gives
#                                             flexref::<folder> and flexref::flexref (all)
#   <prefix>/bin/flexref                      the command line
#   <prefix>/share/flexref/plots/             the plot scripts the studies run
#
# Inside the project headers include each other as "core/model.hpp" (the source root is on the
# include path). Installed, they live under include/flexref/ and are rewritten at install time
# to include "flexref/core/model.hpp", so a user's include path holds only <prefix>/include and
# a user's own "core/..." headers never collide with flexref's (cmake/FlexrefInstallHeaders.cmake).
include(CMakePackageConfigHelpers)

# Headers that are implementation details (SUNDIALS and toml11 types, scheme internals): not
# installed; no installed header includes them.
set(FLEXREF_INTERNAL_HEADERS
  lie/c1_newton.hpp lie/nmb_newton.hpp lie/scheme_support.hpp
  reference/dae_coloured_jacobian.hpp reference/ida_newton_solver.hpp
  reference/ida_work_completion.hpp reference/newton_linear_solver.hpp reference/sundials_handle.hpp
  reference/sundials_ode_callbacks.hpp reference/sundials_segment_driver.hpp
  reference/arkode_segment_solver.hpp reference/ida_callbacks.hpp
  reference/custom_linear_solver.hpp reference/cvode_support.hpp
  scene/reader_parts.hpp scene/scene_toml.hpp precision/multibody_model_impl.hpp)

# The build tree offers the same <flexref/...> prefix (links to the source folders), so code
# written against the installed package (examples/cpp) also compiles inside the project.
file(MAKE_DIRECTORY ${PROJECT_BINARY_DIR}/include/flexref)
foreach(folder ${FLEXREF_LIBRARY_FOLDERS})
  file(CREATE_LINK ${PROJECT_SOURCE_DIR}/${folder} ${PROJECT_BINARY_DIR}/include/flexref/${folder}
       SYMBOLIC)
endforeach()
add_library(flexref_build_prefix INTERFACE)
target_include_directories(flexref_build_prefix INTERFACE ${PROJECT_BINARY_DIR}/include)

# flexref::flexref: every library.
add_library(flexref_all INTERFACE)
set_target_properties(flexref_all PROPERTIES EXPORT_NAME flexref)
add_library(flexref::flexref ALIAS flexref_all)
set(flexref_library_targets)
foreach(folder ${FLEXREF_LIBRARY_FOLDERS})
  list(APPEND flexref_library_targets flexref_${folder})
endforeach()
target_link_libraries(flexref_all INTERFACE ${flexref_library_targets})
# A sanitized build's libraries call the sanitizers' runtimes, and Eigen allocates otherwise under
# AddressSanitizer (handmade aligned blocks where glibc's malloc would do, Eigen/src/Core/util/
# Memory.h): whoever uses one compiles and links with the sanitizers too.
if(FLEXREF_SANITIZE)
  foreach(target ${flexref_library_targets})
    target_compile_options(${target} INTERFACE -fsanitize=address,undefined)
    target_link_options(${target} INTERFACE -fsanitize=address,undefined)
  endforeach()
endif()

install(TARGETS ${flexref_library_targets} flexref_all EXPORT flexrefTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS flexref RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(EXPORT flexrefTargets NAMESPACE flexref:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/flexref)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/flexrefConfig.cmake.in
  ${PROJECT_BINARY_DIR}/flexrefConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/flexref)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/flexrefConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/flexrefConfig.cmake
              ${PROJECT_BINARY_DIR}/flexrefConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/flexref)

file(GLOB flexref_plot_scripts ${PROJECT_SOURCE_DIR}/studies/*.py)
install(FILES ${flexref_plot_scripts} DESTINATION ${CMAKE_INSTALL_DATADIR}/flexref/plots)

# The stepper conformance suite and the test problems it uses, for users' own tests (Catch2 v2):
# include/flexref/testing/.
set(FLEXREF_TESTING_HEADERS tests/support/stepper_conformance.hpp tests/support/test_problems.hpp)

install(CODE "
  set(FLEXREF_TESTING_HEADERS \"${FLEXREF_TESTING_HEADERS}\")
  set(FLEXREF_SOURCE_DIR \"${PROJECT_SOURCE_DIR}\")
  set(FLEXREF_HEADER_FOLDERS \"${FLEXREF_LIBRARY_FOLDERS};studies/mpi\")
  set(FLEXREF_INTERNAL_HEADERS \"${FLEXREF_INTERNAL_HEADERS}\")
  set(FLEXREF_INCLUDE_DESTINATION \"${CMAKE_INSTALL_INCLUDEDIR}/flexref\")")
install(SCRIPT ${PROJECT_SOURCE_DIR}/cmake/FlexrefInstallHeaders.cmake)
