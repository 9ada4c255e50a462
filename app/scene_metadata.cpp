#include <chrono>
#include <ctime>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "app/commands.hpp"

namespace flexref::app {

std::string toml_string_array(const std::vector<std::string>& items) {
  std::ostringstream out;
  out << '[';
  for (std::size_t i = 0; i < items.size(); ++i) out << (i ? ", " : "") << '"' << items[i] << '"';
  out << ']';
  return out.str();
}

std::string toml_number_array(const std::vector<double>& items) {
  std::ostringstream out;
  out.precision(17);
  out << '[';
  for (std::size_t i = 0; i < items.size(); ++i) out << (i ? ", " : "") << items[i];
  out << ']';
  return out.str();
}

core::FlexibleFormulation parse_formulation(const std::string& model) {
  if (model == "coupled") return core::FlexibleFormulation::kCoupled;
  if (model == "lte") return core::FlexibleFormulation::kLte;
  throw std::invalid_argument("unknown --model \"" + model + "\"; expected coupled or lte");
}

std::string reference_solver_for(const core::Model& model, const std::string& solver,
                                 const std::string& option) {
  if (!model.has_flexible_bodies()) return solver;
  if (solver == "exact") {
    throw std::invalid_argument(option +
                                " exact: the scene has flexible bodies, which have no analytic "
                                "solution; use cvode, ida or odeint");
  }
  return solver == "auto" ? "cvode" : solver;
}

std::string scene_metadata(const std::string& scene_file, const scene::Scene& scene) {
  std::ostringstream out;
  std::error_code ec;
  const auto absolute = std::filesystem::absolute(scene_file, ec);
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  int flexible_bodies = 0;
  for (const core::Body& b : scene.model->bodies()) flexible_bodies += b.is_flexible() ? 1 : 0;
  out << "[scene]\n"
      << "file = \"" << (ec ? scene_file : absolute.string()) << "\"\n"
      << "name = \"" << scene.name << "\"\n"
      << "created = \"" << stamp << "\"\n"
      << "model = \"" << core::to_string(scene.model->formulation()) << "\"\n"
      << "flexible_bodies = " << flexible_bodies << "\n";
  return out.str();
}

}  // namespace flexref::app
