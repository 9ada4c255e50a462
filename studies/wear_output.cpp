#include "studies/wear_output.hpp"

#include <cstddef>
#include <sstream>

namespace flexref::studies {
namespace {

std::ostringstream csv_stream() {
  std::ostringstream out;
  out.precision(12);
  return out;
}

}  // namespace

std::string wear_path_csv(const CycleJumpResult& result) {
  std::ostringstream out = csv_stream();
  out << "slow_time";
  for (std::size_t c = 0; c < result.channels.size(); ++c) {
    const std::string& name = result.channels[c];
    out << ',' << name << ".wear_depth," << name << ".wear_volume";
    for (int j = 1; j <= result.channel_count[c]; ++j) out << ',' << name << ".depth" << j;
  }
  out << '\n';
  for (const WearPathPoint& p : result.path) {
    out << p.slow_time;
    for (std::size_t c = 0; c < result.channels.size(); ++c) {
      const Eigen::VectorXd h = p.depth.segment(result.channel_first[c], result.channel_count[c]);
      double volume = 0.0;
      for (Eigen::Index j = 0; j < h.size(); ++j) {
        volume += result.depth_areas[static_cast<std::size_t>(result.channel_first[c] + j)] * h(j);
      }
      out << ',' << h.maxCoeff() << ',' << volume;
      for (Eigen::Index j = 0; j < h.size(); ++j) out << ',' << h(j);
    }
    out << '\n';
  }
  return out.str();
}

std::string wear_profile_csv(const CycleJumpResult& result, const Eigen::VectorXd& depth,
                             const Eigen::VectorXd& reference) {
  std::ostringstream out = csv_stream();
  const bool with_reference = reference.size() == depth.size() && reference.size() > 0;
  out << "contact,index,angle_deg,depth" << (with_reference ? ",reference_depth" : "") << '\n';
  for (std::size_t c = 0; c < result.channels.size(); ++c) {
    const int sectors = result.channel_sectors[c];
    for (int j = 0; j < result.channel_count[c]; ++j) {
      const Eigen::Index k = result.channel_first[c] + j;
      out << result.channels[c] << ',' << j + 1 << ',';
      // A sector's centre, (j + ½) 360°/S from the support's e1 (contact/gap_support.hpp).
      if (sectors > 0) out << (j + 0.5) * 360.0 / sectors;
      out << ',' << depth(k);
      if (with_reference) out << ',' << reference(k);
      out << '\n';
    }
  }
  return out.str();
}

std::string wear_windows_csv(const CycleJumpResult& result) {
  std::ostringstream out = csv_stream();
  out << "window,jump,role,slow_time,max_depth,max_rate,impacts_per_second,cpu,steps\n";
  for (std::size_t i = 0; i < result.windows.size(); ++i) {
    const WearWindow& w = result.windows[i];
    out << i << ',' << w.jump << ',' << w.role << ',' << w.slow_time << ','
        << (w.depth.size() > 0 ? w.depth.maxCoeff() : 0.0) << ','
        << (w.rate.size() > 0 ? w.rate.maxCoeff() : 0.0) << ',' << w.impacts_per_second << ','
        << w.cpu_seconds << ',' << w.steps << '\n';
  }
  return out.str();
}

}  // namespace flexref::studies
