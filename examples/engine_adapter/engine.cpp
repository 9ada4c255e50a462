#include "examples/engine_adapter/engine.hpp"

namespace flexref::engines {

MappingError::MappingError(const scene::SpecSource& source, const std::string& why)
    : std::runtime_error(source.file + ":" + std::to_string(source.line) + ": key '" + source.path +
                         "': " + why) {}

MappingError::MappingError(const std::string& option, const std::string& why)
    : std::runtime_error(option + ": " + why) {}

}  // namespace flexref::engines
