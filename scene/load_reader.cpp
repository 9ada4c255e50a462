/// \file load_reader.cpp
/// [[load]] and [[potential]] tables (scenes/README.md) into LoadSpec and PotentialSpec.
#include <Eigen/Core>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rotation/euler_parameters.hpp"
#include "scene/reader_parts.hpp"

namespace flexref::scene::detail {

namespace {

core::TimeProfile read_profile(const Table& load) {
  const std::optional<Table> p =
      load.table("profile",
                 "a profile { shape = \"constant\" | \"sin2_pulse\" | \"rectangular_pulse\" | "
                 "\"harmonic\", start, duration | frequency, phase }");
  if (!p) return core::TimeProfile::constant();
  p->check_keys({"shape", "start", "duration", "frequency", "phase"});
  const int shape =
      p->choice("shape", {"constant", "sin2_pulse", "rectangular_pulse", "harmonic"}, -1);
  if (shape == 3) {
    reject_keys(*p, {"start", "duration"}, "applies only to pulses");
    const double frequency = p->number("frequency", Sign::kPositive, "a positive frequency in Hz");
    const double phase = p->number_or("phase", 0.0, Sign::kAny, "a phase in rad");
    return core::TimeProfile::harmonic(frequency, phase);
  }
  reject_keys(*p, {"frequency", "phase"}, "applies only to shape = \"harmonic\"");
  if (shape == 0) {
    for (const std::string_view key : {"start", "duration"}) {
      if (p->has(key)) {
        p->fail(key, "applies only to pulses; expected no " + std::string(key) +
                         " with shape = \"constant\"");
      }
    }
    return core::TimeProfile::constant();
  }
  const double start = p->number_or("start", 0.0, Sign::kAny, "a pulse start time in s");
  const double duration = p->number("duration", Sign::kPositive, "a positive pulse duration in s");
  if (!std::isfinite(start + duration)) {
    p->fail("duration", "expected a pulse that ends at a finite time, got start + duration = " +
                            format(start + duration));
  }
  try {
    return shape == 1 ? core::TimeProfile::sin2_pulse(start, duration)
                      : core::TimeProfile::rectangular_pulse(start, duration);
  } catch (const std::exception& e) {
    p->fail_table(e.what());
  }
}

}  // namespace

LoadSpec read_load(const Table& t, const BodyNames& names, const std::vector<BodySpec>& bodies) {
  t.check_keys({"kind", "body", "value", "frame", "at", "node", "profile"});
  const bool torque = t.choice("kind", {"torque", "force"}, -1) == 0;
  const int body = names.resolve(t, "body");
  const Eigen::Vector3d value =
      t.vector3("value", torque ? "the torque [x, y, z] in N*m" : "the force [x, y, z] in N");
  const core::LoadFrame frame = t.choice("frame", {"world", "body"}, 0) == 0
                                    ? core::LoadFrame::kWorld
                                    : core::LoadFrame::kBody;
  if (torque && t.has("at")) {
    t.fail("at", "applies only to forces (a torque is a couple); expected no at for a torque");
  }
  if (torque && t.has("node")) {
    t.fail("node", "applies only to forces (a torque is a couple); expected no node for a torque");
  }
  if (t.has("node") && t.has("at")) {
    t.fail("at", "a node force acts at its node; expected either at or node, not both");
  }
  int node = -1;
  Eigen::Vector3d at = Eigen::Vector3d::Zero();
  if (t.has("node")) {
    const BodySpec& b = bodies[static_cast<std::size_t>(body)];
    node = read_node(t, "node", b);
    at = b.description.flexible->modal.p_BoNode_B.col(node);
  } else {
    at = t.vector3_or("at", Eigen::Vector3d::Zero(),
                      "the point of application [x, y, z] in m, body frame");
  }
  LoadSpec spec;
  spec.node = node;
  spec.torque = torque;
  spec.body = body;
  spec.value = value;
  spec.frame = frame;
  spec.p_BoP_B = at;
  spec.profile = read_profile(t);
  spec.source = source_of(t);
  return spec;
}

PotentialSpec read_potential(const Table& t, const BodyNames& names,
                             const std::vector<BodySpec>& bodies) {
  t.check_keys({"kind", "alpha", "beta", "attractor", "charges"});
  t.choice("kind", {"point_charge"}, -1);
  const double alpha =
      t.number("alpha", Sign::kNonNegative, "a non-negative attraction strength alpha in J*m");
  const double beta =
      t.number("beta", Sign::kNonNegative, "a non-negative wall repulsion strength beta in J*m");
  const Eigen::Vector3d p_WM =
      t.vector3("attractor", "the attracting point [x, y, z] in m, world frame");
  const std::vector<Table> tables =
      t.tables("charges", "an array of charges { body = \"...\", at = [x, y, z], weight = c }");
  if (tables.empty()) {
    t.fail("charges", "expected at least one charge { body = \"...\", at = [x, y, z], weight }");
  }
  std::vector<core::PointChargePotential::Charge> charges;
  for (const Table& c : tables) {
    c.check_keys({"body", "at", "weight"});
    core::PointChargePotential::Charge charge;
    charge.body = names.resolve(c, "body");
    charge.p_BoP_B = c.vector3("at", "the charge position [x, y, z] in m, body frame");
    charge.weight = c.number_or("weight", 1.0, Sign::kPositive, "a positive charge weight");
    // The potential is singular on the wall z = 0 and at the attractor, and defined above
    // the wall only: the charge must start there.
    const core::BodyInitialState& init =
        bodies[static_cast<std::size_t>(charge.body)].description.initial;
    const Eigen::Vector3d p_WP =
        init.p_WBo + rotation::rotation_matrix(init.theta_WB) * charge.p_BoP_B;
    if (!(p_WP.z() > 0.0)) {
      c.fail("at", "the charge starts at z = " + format(p_WP.z()) +
                       "; expected a charge above the wall z = 0");
    }
    if (!((p_WP - p_WM).norm() > 0.0)) {
      c.fail("at", "the charge starts on the attractor; expected a charge away from it");
    }
    charges.push_back(charge);
  }
  PotentialSpec spec;
  spec.alpha = alpha;
  spec.beta = beta;
  spec.p_WM = p_WM;
  spec.charges = std::move(charges);
  spec.source = source_of(t);
  return spec;
}

}  // namespace flexref::scene::detail
