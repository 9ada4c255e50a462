/// \file serial_session.cpp
/// The process session of a build without MPI (studies/mpi/distribution.hpp): this process alone.
/// studies/mpi/mpi_session.cpp replaces this file when CMake finds MPI.
#include "studies/mpi/distribution.hpp"

namespace flexref::studies {

struct ProcessSession::Impl {};

ProcessSession::ProcessSession(int& /*argc*/, char**& /*argv*/) {}

ProcessSession::~ProcessSession() = default;

int ProcessSession::finish(int exit_code) { return exit_code; }

}  // namespace flexref::studies
