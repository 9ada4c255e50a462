#include "app/scene_metadata.hpp"

#include <chrono>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <stdexcept>

namespace flexref::app {

trajectory::SceneIdentity scene_identity(const std::string& scene_file, const scene::Scene& scene) {
  std::error_code ec;
  const auto absolute = std::filesystem::absolute(scene_file, ec);
  return {scene.name, scene.hash, ec ? scene_file : absolute.string(),
          core::to_string(scene.model->formulation())};
}

std::string check_same_scene(const trajectory::SceneIdentity& a, const std::string& a_what,
                             const trajectory::SceneIdentity& b, const std::string& b_what,
                             bool allow) {
  const std::string mismatch = trajectory::scene_mismatch(a, a_what, b, b_what);
  if (mismatch.empty()) return mismatch;
  if (!allow) {
    throw std::invalid_argument(mismatch +
                                "; nothing compared (--allow-scene-mismatch compares them anyway)");
  }
  std::cerr << "flexref: warning: " << mismatch << " (compared anyway: --allow-scene-mismatch)\n";
  return mismatch;
}

studies::StudyRecord scene_record(const std::string& scene_file, const scene::Scene& scene) {
  const trajectory::SceneIdentity identity = scene_identity(scene_file, scene);
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  int flexible_bodies = 0;
  for (const core::Body& b : scene.model->bodies()) flexible_bodies += b.is_flexible() ? 1 : 0;
  studies::StudyRecord record;
  studies::StudyRecord::Table& table =
      record.table("scene").set("file", identity.file).set("name", identity.name);
  if (!identity.hash.empty()) table.set("hash", identity.hash);
  table.set("created", std::string(stamp))
      .set("model", core::to_string(scene.model->formulation()))
      .set("flexible_bodies", flexible_bodies);
  // Each contact's wear law (docs/wear.md): what its depths mean and the acceleration factor
  // that multiplies the laboratory coefficient, never hidden.
  const core::Model& model = *scene.model;
  for (int c = 0; c < model.wear_channel_count(); ++c) {
    const core::WearLaw* law = model.channel_wear_law(c);
    if (law == nullptr) continue;
    studies::StudyRecord::Table& wear = record.append("wear");
    wear.set("contact", model.wear_channel_names()[static_cast<std::size_t>(c)])
        .set("law", std::string(law->name()))
        .set("coefficient", law->coefficient)
        .set("acceleration", law->acceleration);
    if (law->kind == core::WearLaw::Kind::kArchard) wear.set("hardness", law->hardness);
    if (law->sectors > 0) {
      wear.set("sectors", law->sectors).set("radius", law->radius).set("thickness", law->thickness);
    } else {
      wear.set("area", law->area);
    }
    wear.set("depths", model.channel_depth_count(c));
  }
  return record;
}

}  // namespace flexref::app
