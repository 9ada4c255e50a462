#include "app/lte_map_command.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "app/commands.hpp"
#include "core/error.hpp"
#include "scene/scene_reader.hpp"
#include "scene/scene_toml.hpp"
#include "studies/lte_map.hpp"
#include "studies/parallel.hpp"
#include "studies/plot.hpp"
#include "studies/study_output.hpp"
#include "studies/trajectory_table.hpp"

namespace flexref::app {
namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (!in && !in.eof()) throw core::InputError(path, 0, "", "cannot read the scene file");
  return std::move(buffer).str();
}

toml::array toml_vector(const Eigen::Vector3d& v) { return toml::array{v(0), v(1), v(2)}; }

bool close(double a, double b) { return std::abs(a - b) <= 1e-14 * std::max(std::abs(b), 1.0); }

/// Builds the scene's model with a grid point's changes, by editing the parsed TOML document
/// (body[i].mass, .inertia, .angular_velocity; every [[load]] value) and reading it again, so
/// the force elements are built exactly as for the scene itself. Each call parses afresh: safe
/// from several threads.
class SceneFactory {
 public:
  SceneFactory(std::string path, int body_index)
      : path_(std::move(path)), text_(read_text(path_)), body_index_(body_index) {}

  core::Model operator()(core::FlexibleFormulation formulation,
                         const std::optional<studies::LteMapScaling>& scaling) const {
    if (!scaling) return std::move(*scene::parse_scene(text_, path_, formulation).model);
    const core::Model scene_model = std::move(*scene::parse_scene(text_, path_, formulation).model);
    const core::RigidBodyDescription& d = scene_model.body(body_index_).description();
    const double mass = scaling->hub_scale * d.mass;
    const Eigen::Matrix3d inertia = scaling->hub_scale * d.I_Bcm_B;

    toml::value document = scene::scene_toml::parse(text_, path_);
    toml::table& body = document.as_table()
                            .at("body")
                            .as_array()
                            .at(static_cast<std::size_t>(body_index_))
                            .as_table();
    body["mass"] = mass;
    body["inertia"] = toml::array{toml_vector(inertia.row(0).transpose()),
                                  toml_vector(inertia.row(1).transpose()),
                                  toml_vector(inertia.row(2).transpose())};
    body["angular_velocity"] = toml_vector(scaling->w0_WB_B);
    if (document.as_table().count("load") != 0) {
      for (toml::value& load : document.as_table().at("load").as_array()) {
        toml::table& t = load.as_table();
        if (t.count("value") == 0) continue;
        Eigen::Vector3d value;
        for (int k = 0; k < 3; ++k) {
          const toml::value& x = t.at("value").as_array().at(static_cast<std::size_t>(k));
          value(k) = x.is_integer() ? static_cast<double>(x.as_integer()) : x.as_floating();
        }
        t["value"] = toml_vector(scaling->load_scale * value);
      }
    }
    // toml11 writes floats with max_digits10 digits: the values read back are the ones set.
    core::Model model =
        std::move(*scene::parse_scene(toml::format(document), path_, formulation).model);
    const core::RigidBodyDescription& e = model.body(body_index_).description();
    if (!close(e.mass, mass) || !close(e.I_Bcm_B(2, 2), inertia(2, 2)) ||
        !close(e.initial.w_WB_B.norm(), scaling->w0_WB_B.norm())) {
      throw std::logic_error("lte-map: the edited scene did not keep the grid point's values");
    }
    return model;
  }

 private:
  std::string path_;
  std::string text_;
  int body_index_;
};

std::string number(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

std::vector<double> ratios(const std::vector<double>& given, double lo, double hi, int count,
                           const std::string& option) {
  if (!given.empty()) {
    for (const double v : given) {
      if (!(v > 0.0) || !std::isfinite(v)) {
        throw std::invalid_argument("lte-map: --" + option + "-ratios must be positive, got " +
                                    number(v));
      }
    }
    return given;
  }
  try {
    return studies::log_spaced_values(lo, hi, count);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("lte-map: --" + option + "-min/max/count: " + e.what());
  }
}

}  // namespace

int lte_map_command(const LteMapCommandOptions& options) {
  const scene::Scene scene = scene::read_scene(options.scene);
  studies::LteMapOptions study;
  study.spin_ratios =
      ratios(options.spin_ratios, options.spin_min, options.spin_max, options.spin_count, "spin");
  study.inertia_ratios = ratios(options.inertia_ratios, options.inertia_min, options.inertia_max,
                                options.inertia_count, "inertia");
  study.end_time = options.end_time > 0.0 ? options.end_time : scene.end_time;
  study.output_step = std::min(scene.output_step, study.end_time);
  study.solver = reference_solver_for(*scene.model, options.solver, "--solver");
  study.rtol = options.rtol;
  study.estimate_factor = options.estimate_factor;
  study.scale_loads = options.scale_loads;
  study.point = options.point;
  study.jobs = options.jobs > 0 ? options.jobs : studies::default_jobs();
  study.progress = true;
  // Validate the scene (and find the body) before starting the grid.
  const studies::LteMapBase base = studies::lte_map_base(*scene.model, study);
  study.body = scene.model->body_index(base.body);
  const SceneFactory factory(options.scene, study.body);

  studies::StudyOutput out(options.out_dir);
  std::cerr << "lte-map: " << study.spin_ratios.size() * study.inertia_ratios.size()
            << " grid points x 4 reference runs (" << study.solver << ", rtol " << study.rtol
            << ", " << study.end_time << " s) on " << study.jobs << " threads ...\n";
  const studies::LteMapResult result = studies::run_lte_map(factory, study);

  const std::string table = studies::format_lte_map_table(result);
  studies::StudyRecord record = scene_record(options.scene, scene);
  record.table("study")
      .set("kind", "lte-map")
      .set("body", base.body)
      .set("point", base.point)
      .set("spin_ratios", study.spin_ratios)
      .set("inertia_ratios", study.inertia_ratios)
      .set("omega1", base.omega1)
      .set("omega1_meaning", "rad/s, first clamped frequency")
      .set("scene_spin", base.spin)
      .set("scene_spin_ratio", base.spin_ratio)
      .set("scene_inertia_ratio", base.inertia_ratio)
      .set("spin_axis_B", std::vector<double>{base.axis_B(0), base.axis_B(1), base.axis_B(2)})
      .set("scale", std::string("hub mass and inertia by hub_scale; initial spin to x*omega1") +
                        (study.scale_loads ? "; [[load]] values by load_scale" : ""))
      .set("scale_loads", study.scale_loads)
      .set("metric",
           "max_t |d_LTE - d_coupled| / max_t |d_coupled|, d = elastic deflection of the point, "
           "body frame")
      .set("solver", study.solver)
      .set("rtol", study.rtol)
      .set("estimate_rtol", study.estimate_factor * study.rtol)
      .set("end_time", study.end_time)
      .set("output_step", study.output_step)
      .set("jobs", study.jobs);
  studies::add_versions(record);

  out.write("lte_map.csv", studies::lte_map_csv(result));
  out.write("lte_map.txt", table);
  const studies::PlotOutcome plot =
      out.plot("plot_lte_map.py", "lte_map.png",
               {out.staged("lte_map.csv"), out.staged("lte_map.png"),
                "LTE error on " + scene.name + " (" + number(study.end_time) + " s)",
                number(base.spin_ratio), number(base.inertia_ratio)});
  const std::string csv_path = out.final_path("lte_map.csv");
  out.commit(std::move(record));

  std::cout << "lte-map\n" << table << "wrote " << csv_path << ", lte_map.txt, study.toml";
  if (plot.ok) std::cout << ", " << plot.message;
  std::cout << "\n";
  if (!plot.ok) std::cout << plot.message << "\n";
  return kExitOk;
}

}  // namespace flexref::app
