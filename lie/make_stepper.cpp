/// \file make_stepper.cpp
/// The method registry (lie/method_registry.hpp) with the built-in schemes, and make_stepper /
/// scheme_names on top of it.
#include <algorithm>
#include <deque>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

#include "lie/c1.hpp"
#include "lie/c2.hpp"
#include "lie/genalpha.hpp"
#include "lie/genalpha_parameters.hpp"
#include "lie/method_options.hpp"
#include "lie/method_registry.hpp"
#include "lie/nmb.hpp"
#include "lie/stepper.hpp"

namespace flexref::lie {
namespace {

// Entries are only ever appended, and a std::deque keeps the address of every element on
// push_back, so the pointer find_method returns stays valid while others register.
struct Registry {
  std::mutex mutex;
  std::deque<MethodInfo> methods;
};

Registry& registry() {
  static Registry* r = [] {
    auto* reg = new Registry;  // never destroyed: steppers may be built during static teardown
    reg->methods.push_back({"c1", 2, "Simo-Wong C1 (implicit, energy-momentum)",
                            [](const core::Model& m, const MethodOptions&) {
                              return std::make_unique<C1Stepper>(m);
                            }});
    reg->methods.push_back({"c2", 2, "Simo-Wong C2 (explicit, momentum-conserving)",
                            [](const core::Model& m, const MethodOptions&) {
                              return std::make_unique<C2Stepper>(m);
                            }});
    reg->methods.push_back({"nmb", 2, "Krysl-Endres NMB (explicit Newmark on the Lie group)",
                            [](const core::Model& m, const MethodOptions&) {
                              return std::make_unique<NmbStepper>(m);
                            }});
    // The comparison method, with the caller's ρ∞ and start (--rho-inf, --perturbed-start); run
    // when named.
    reg->methods.push_back(
        {"genalpha", 2, "Lie-group generalized-alpha (Bruls-Cardona-Arnold 2012, implicit)",
         [](const core::Model& m, const MethodOptions& options) {
           GenAlphaParameters parameters = GenAlphaParameters::from_rho_inf(options.rho_inf);
           parameters.perturbed_start = options.perturbed_start;
           return std::make_unique<GenAlphaStepper>(m, parameters);
         },
         false});
    return reg;
  }();
  return *r;
}

bool valid_name(const std::string& name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  });
}

}  // namespace

void register_method(MethodInfo method) {
  if (!valid_name(method.name)) {
    throw std::invalid_argument("register_method: name '" + method.name +
                                "' must be letters, digits, '_' and '-'");
  }
  if (method.claimed_order < 1) {
    throw std::invalid_argument("register_method: " + method.name +
                                ": the claimed order must be at least 1");
  }
  if (!method.factory) {
    throw std::invalid_argument("register_method: " + method.name + ": no factory");
  }
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  for (const MethodInfo& m : r.methods) {
    if (m.name == method.name) {
      throw std::invalid_argument("register_method: '" + method.name + "' is already registered");
    }
  }
  r.methods.push_back(std::move(method));
}

const MethodInfo* find_method(std::string_view name) {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  for (const MethodInfo& m : r.methods) {
    if (m.name == name) return &m;
  }
  return nullptr;
}

std::vector<MethodInfo> registered_methods() {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  return {r.methods.begin(), r.methods.end()};
}

void check_method_options(const MethodOptions& options, const std::vector<std::string>& schemes) {
  for (const auto& entry : options.values) {
    const std::string& option = entry.first;
    bool read = false;
    for (const std::string& scheme : schemes) {
      const MethodInfo* method = find_method(scheme);
      if (method == nullptr) continue;
      const std::vector<std::string>& names = method->option_names;
      read = read || std::find(names.begin(), names.end(), option) != names.end();
    }
    if (read) continue;
    std::string list;
    for (const std::string& s : schemes) list += (list.empty() ? "" : ", ") + s;
    throw std::invalid_argument("method option '" + option + "' is read by none of the schemes (" +
                                (list.empty() ? std::string("none") : list) +
                                "): a method declares the options it reads in "
                                "MethodInfo::option_names");
  }
}

std::unique_ptr<Stepper> make_stepper(std::string_view name, const core::Model& model,
                                      const MethodOptions& options) {
  const MethodInfo* method = find_method(name);
  if (method == nullptr) {
    std::string known;
    for (const std::string& n : scheme_names()) known += (known.empty() ? "" : ", ") + n;
    throw std::invalid_argument("unknown scheme '" + std::string(name) + "' (expected one of " +
                                known + ")");
  }
  return method->factory(model, options);
}

std::vector<std::string> scheme_names() {
  std::vector<std::string> names;
  for (const MethodInfo& m : registered_methods()) names.push_back(m.name);
  return names;
}

std::vector<std::string> default_scheme_names() {
  std::vector<std::string> names;
  for (const MethodInfo& m : registered_methods()) {
    if (m.in_default_studies) names.push_back(m.name);
  }
  return names;
}

std::vector<std::string> builtin_scheme_names() { return {"c1", "c2", "nmb"}; }

}  // namespace flexref::lie
