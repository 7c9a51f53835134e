#include "core/json_text.hpp"

#include <nlohmann/json.hpp>

namespace softcut {

std::string json_string(std::string_view s) {
  return nlohmann::json(std::string(s)).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace softcut
