#pragma once
/// \file trajectory_writer.hpp
/// Writes an engine's samples under flexref's trajectory contract (docs/external.md): `t`,
/// then per body B the columns B.x B.y B.z, B.e0 … B.e3 (Euler parameters body→world, scalar
/// first), B.vx B.vy B.vz, B.W1 B.W2 B.W3 (body-frame angular velocity) and per tracked point P
/// B.P.x B.P.y B.P.z, every value with 17 significant digits, and the engine's CPU time as
/// `# cpu_seconds = X`. The file is written under a
/// temporary name in the output's folder and renamed when complete: a failed run leaves no
/// file, never a partial one.
#include <cstdio>
#include <string>
#include <vector>

#include "examples/engine_adapter/engine.hpp"
#include "scene/scene.hpp"

namespace flexref::engines {

/// The output file cannot be created or written (exit code 5).
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class TrajectoryWriter {
 public:
  /// Opens the temporary file and writes the header. Throws OutputError.
  TrajectoryWriter(const std::string& path, const scene::Scene& scene);
  ~TrajectoryWriter();
  TrajectoryWriter(const TrajectoryWriter&) = delete;
  TrajectoryWriter& operator=(const TrajectoryWriter&) = delete;

  /// One row at time t. Throws core::SolverError (naming `engine` and step n) when a value is
  /// not finite, and OutputError when the row cannot be written.
  void write_row(double t, long n, const std::vector<BodySample>& bodies,
                 const std::string& engine);
  /// The comment `# cpu_seconds = X`: the CPU time of the integration alone (docs/external.md).
  void write_cpu_seconds(double seconds);
  /// Closes the file and renames it to the output path. Throws OutputError.
  void commit();

 private:
  const scene::Scene& scene_;
  std::string path_;
  std::string temporary_;
  std::FILE* file_ = nullptr;
};

}  // namespace flexref::engines
