#include <chrono>
#include <ctime>
#include <filesystem>
#include <sstream>

#include "app/commands.hpp"

namespace flexref::app {

std::string scene_metadata(const std::string& scene_file, const std::string& scene_name) {
  std::ostringstream out;
  std::error_code ec;
  const auto absolute = std::filesystem::absolute(scene_file, ec);
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  out << "[scene]\n"
      << "file = \"" << (ec ? scene_file : absolute.string()) << "\"\n"
      << "name = \"" << scene_name << "\"\n"
      << "created = \"" << stamp << "\"\n";
  return out.str();
}

}  // namespace flexref::app
