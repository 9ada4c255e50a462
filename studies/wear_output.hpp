#pragma once
/// \file wear_output.hpp
/// The files of the wear commands (docs/wear.md): the depths against slow time, the worn
/// profile, the windows taken; CSV text only (the commands stage and write them).
#include <string>

#include "studies/wear_cycle_jump.hpp"

namespace flexref::studies {

/// One row per slow time of the path: slow_time, then per worn contact C its C.wear_depth (the
/// largest depth), C.wear_volume and C.depth1 … C.depthN, m and m³.
std::string wear_path_csv(const CycleJumpResult& result);

/// The worn profile at the end: contact,index,angle_deg,depth[,reference_depth] per point or
/// sector (angle_deg: a sector's centre about the support's axis, docs/wear.md; empty for a
/// point). `reference` (empty: none) adds the reference's depths.
std::string wear_profile_csv(const CycleJumpResult& result, const Eigen::VectorXd& depth,
                             const Eigen::VectorXd& reference = {});

/// One row per window: window,jump,role,slow_time,max_depth,max_rate,impacts_per_second,cpu,
/// steps.
std::string wear_windows_csv(const CycleJumpResult& result);

}  // namespace flexref::studies
