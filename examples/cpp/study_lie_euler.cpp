/// A user's own stepper (lie_euler_stepper.hpp) registered with flexref's method registry and
/// studied like a built-in scheme: the convergence study against a certified reference, on
/// the first 10 s of a scene (default scenes/free_spin.toml). Exits 1 unless the observed
/// order is 1 ± 0.1, as the method claims.
#include <cmath>
#include <cstdio>
#include <exception>
#include <flexref/core/output_times.hpp>
#include <flexref/scene/scene_reader.hpp>
#include <flexref/studies/convergence.hpp>
#include <iostream>
#include <string>

#include "lie_euler_stepper.hpp"

int main(int argc, char** argv) {
  try {
    user::register_lie_euler();
    const std::string path = argc > 1 ? argv[1] : "scenes/free_spin.toml";
    const flexref::scene::Scene scene = flexref::scene::read_scene(path);
    const std::vector<double> times =
        flexref::core::output_times(std::min(10.0, scene.end_time), scene.output_step);

    flexref::studies::ConvergenceOptions options;
    options.schemes = {"lie_euler", "c2"};  // the user's method beside a built-in one
    options.h0 = 0.02;
    options.levels = 4;
    const flexref::studies::ConvergenceResult result =
        flexref::studies::run_convergence(*scene.model, times, options);
    std::cout << flexref::studies::format_convergence_table(result);

    const double order = result.summaries.front().fitted_order;
    if (!(std::abs(order - 1.0) <= 0.1)) {
      std::cerr << "lie_euler: observed order " << order << ", claimed 1\n";
      return 1;
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "study_lie_euler: " << e.what() << "\n";
    return 2;
  }
}
