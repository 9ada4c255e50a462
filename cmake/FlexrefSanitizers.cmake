# -DFLEXREF_SANITIZE=ON builds everything with AddressSanitizer and UBSan.
# UBSan without its `null` and `alignment` checks: they instrument every pointer access and cost a
# third of this build's compile time (measured on a test batch: 23.5 s with them, 15.6 s
# without, 15.2 s for ASan alone), while a null access still ends the test with ASan's SEGV
# report and its stack, and x86-64 tolerates the misaligned loads the second would flag. The
# checks that found defects here (invalid enum and bool loads, bounds, shifts, overflow) stay.
if(FLEXREF_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize=null,alignment
                      -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()
