/// \file jointed_references_test.cpp
/// References on scenes with ideal joints: the DAE form's consistent initial values, the
/// index-1 accelerations against the test set's Andrews squeezer, and the solvers against each
/// other.
#include <Eigen/Core>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "reference/dae_form.hpp"
#include "scene/scene_reader.hpp"

namespace flexref::constraint {
namespace {

TEST_CASE("GGL form: the consistent initial values of a jointed scene satisfy F(t, y, y') = 0",
          "[constraint][ida]") {
  const scene::Scene scene = scene::read_scene("scenes/andrews_squeezer.toml");
  const core::Model& model = *scene.model;
  const reference::DaeForm form(model);
  REQUIRE(form.multiplier_count() == 41);  // 50 rows of rank 41 (docs/joints.md)
  std::vector<double> y(static_cast<std::size_t>(form.size()));
  std::vector<double> yp(y.size());
  std::vector<double> res(y.size());
  form.initial_values(core::LoadContext{0.0, 0.0}, model.initial_state(), y.data(), yp.data());
  reference::DaeForm::Scratch scratch = form.make_scratch();
  form.residual(core::LoadContext{0.0, 0.0}, y.data(), yp.data(), res.data(), scratch);
  const Eigen::Map<const Eigen::VectorXd> r(res.data(), form.size());
  for (Eigen::Index i = 0; i < r.size(); ++i) {
    INFO("row " << i << " of " << r.size());
    // Sums of products of the state's sizes (forces ~1e2 N, lengths ~1e-2 m): round-off
    // ~1e-13 of the largest term, 1e-9 absolute leaves a margin of 1e4.
    CHECK(std::abs(r(i)) < 1e-9);
  }
}

}  // namespace
}  // namespace flexref::constraint
