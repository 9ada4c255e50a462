#pragma once
/// \file build_model.hpp
/// SceneSpec → core::Model: the one place where a scene's bodies and force elements are made
/// (gravity, loads, potentials, contacts, bushing joints, springs, in that order; then the
/// ideal joints), for scenes read from files
/// and for scenes built or varied in code.
#include <stdexcept>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "scene/scene_spec.hpp"

namespace flexref::scene {

/// A part of a spec that cannot be built: which part (its source), the key at fault ("" for the
/// whole table) and why. The scene reader turns it into a core::InputError at that key.
class SpecError : public std::invalid_argument {
 public:
  SpecError(SpecSource source, std::string key, const std::string& what)
      : std::invalid_argument(what), source_(std::move(source)), key_(std::move(key)) {}
  const SpecSource& source() const { return source_; }
  const std::string& key() const { return key_; }

 private:
  SpecSource source_;
  std::string key_;
};

/// Builds the bodies and force elements of the spec. Throws SpecError. `independent_rows`: the
/// ideal joints' rows to keep (core::ConstraintOptions; empty: chosen at the initial
/// configuration), for a model that must solve the rows another one chose, or a test that
/// starts a mechanism on rows it will have to choose again in motion.
core::Model build_model(const SceneSpec& spec,
                        core::FlexibleFormulation formulation = core::FlexibleFormulation::kCoupled,
                        const std::vector<int>& independent_rows = {});

/// Where each force element of build_model(spec) comes from, in the model's order: gravity
/// (path "scene", line 0: SceneSpec keeps no line for it), then every load, potential, contact,
/// bushing joint and spring with its table's source.
std::vector<SpecSource> element_sources(const SceneSpec& spec);

/// How messages name the element of a table (core::ForceElement::label): "spring 'S1'" (the
/// table's kind and name) or, without a name, the table's path ("spring[2]", counted from 1
/// as in the file); "" for a part built in code without a source.
std::string element_label(const SpecSource& source, const std::string& kind,
                          const std::string& name);

/// The contact element of one [[contact]] spec, given the bodies it acts on (for the default
/// effective mass). Throws SpecError.
std::unique_ptr<const core::ForceElement> build_contact(const ContactSpec& contact,
                                                        const std::vector<core::Body>& bodies);

}  // namespace flexref::scene
