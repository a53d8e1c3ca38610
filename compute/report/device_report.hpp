// The device report of `fird info`: every device found, the chosen one, its limits.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "vk/context.hpp"

namespace fird {

nlohmann::json device_report(const vk::Context& ctx);
std::string device_report_text(const nlohmann::json& report);

} // namespace fird
