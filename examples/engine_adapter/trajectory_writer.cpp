#include "examples/engine_adapter/trajectory_writer.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "core/error.hpp"

namespace flexref::engines {
namespace {

std::string system_error(const std::string& what, const std::string& path) {
  return what + " " + path + ": " + std::strerror(errno);
}

}  // namespace

TrajectoryWriter::TrajectoryWriter(const std::string& path, const scene::Scene& scene)
    : scene_(scene), path_(path) {
  const std::filesystem::path target(path);
  const std::filesystem::path folder =
      target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
  std::string pattern = (folder / ("." + target.filename().string() + ".XXXXXX")).string();
  const int fd = mkstemp(pattern.data());
  if (fd < 0) throw OutputError(system_error("cannot create a file beside", path));
  temporary_ = pattern;
  fchmod(fd, 0644);  // mkstemp's 0600 would make the result unreadable to other users
  file_ = fdopen(fd, "w");
  if (file_ == nullptr) {
    close(fd);
    std::filesystem::remove(temporary_);
    throw OutputError(system_error("cannot open", temporary_));
  }
  std::string header = "t";
  for (const scene::BodySpec& body : scene_.spec.bodies) {
    const std::string& b = body.description.name;
    for (const char* c :
         {".x", ".y", ".z", ".e0", ".e1", ".e2", ".e3", ".vx", ".vy", ".vz", ".W1", ".W2", ".W3"}) {
      header += "," + b + c;
    }
    for (const core::TrackedPoint& point : body.description.points) {
      for (const char* c : {".x", ".y", ".z"}) header += "," + b + "." + point.name + c;
    }
  }
  header += "\n";
  if (std::fputs(header.c_str(), file_) < 0) {
    throw OutputError(system_error("cannot write", temporary_));
  }
}

TrajectoryWriter::~TrajectoryWriter() {
  if (file_ != nullptr) std::fclose(file_);
  if (!temporary_.empty()) {
    std::error_code ec;
    std::filesystem::remove(temporary_, ec);
  }
}

void TrajectoryWriter::write_row(double t, long n, const std::vector<BodySample>& bodies,
                                 const std::string& engine) {
  std::vector<double> values{t};
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const BodySample& s = bodies[b];
    for (double v :
         {s.p_WBo.x(), s.p_WBo.y(), s.p_WBo.z(), s.e_WB[0], s.e_WB[1], s.e_WB[2], s.e_WB[3],
          s.v_WBo.x(), s.v_WBo.y(), s.v_WBo.z(), s.w_WB_B.x(), s.w_WB_B.y(), s.w_WB_B.z()}) {
      values.push_back(v);
    }
    const Eigen::Quaterniond q_WB(s.e_WB[0], s.e_WB[1], s.e_WB[2], s.e_WB[3]);
    const Eigen::Matrix3d R_WB = q_WB.normalized().toRotationMatrix();
    for (const core::TrackedPoint& point : scene_.spec.bodies[b].description.points) {
      const Eigen::Vector3d p_WP = s.p_WBo + R_WB * point.p_BoP_B;
      values.insert(values.end(), {p_WP.x(), p_WP.y(), p_WP.z()});
    }
  }
  for (double v : values) {
    if (!std::isfinite(v)) {
      throw core::SolverError(engine, t, n, "the engine's state is not finite (a diverged run)");
    }
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (std::fprintf(file_, i == 0 ? "%.17g" : ",%.17g", values[i]) < 0) {
      throw OutputError(system_error("cannot write", temporary_));
    }
  }
  if (std::fputc('\n', file_) == EOF) throw OutputError(system_error("cannot write", temporary_));
}

void TrajectoryWriter::write_cpu_seconds(double seconds) {
  if (std::fprintf(file_, "# cpu_seconds = %.6g\n", std::max(seconds, 0.0)) < 0) {
    throw OutputError(system_error("cannot write", temporary_));
  }
}

void TrajectoryWriter::commit() {
  const int closed = std::fclose(file_);
  file_ = nullptr;
  if (closed != 0) throw OutputError(system_error("cannot write", temporary_));
  std::error_code ec;
  std::filesystem::rename(temporary_, path_, ec);
  if (ec) throw OutputError("cannot write " + path_ + ": " + ec.message());
  temporary_.clear();
}

}  // namespace flexref::engines
