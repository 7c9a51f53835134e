#include "backend/spec.hpp"

#include <utility>

#include "core/error.hpp"
#include "core/printable.hpp"

namespace softcut::backend {

namespace {
constexpr std::pair<Backend, const char*> kBackendNames[] = {{Backend::automatic, "auto"},
                                                            {Backend::cpu, "cpu"},
                                                            {Backend::gpu, "gpu"},
                                                            {Backend::direct, "direct"},
                                                            {Backend::monolithic, "monolithic"}};
}  // namespace

const char* to_string(Backend b) {
  for (const auto& [v, name] : kBackendNames)
    if (v == b) return name;
  return "?";
}

Backend parse_backend(std::string_view text) {
  for (const auto& [v, name] : kBackendNames)
    if (text == name) return v;
  fail("solver: unknown backend '", printable(text), "' (use auto, cpu, gpu, direct or monolithic)");
}

}  // namespace softcut::backend
