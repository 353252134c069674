// The daemon's replies as a person reads them (reply_text.cpp).
#pragma once

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "slicecap/control/reply_views.hpp"

namespace slicecap::cli {

/// \brief A sweep's bins as a bar of cells, "[##..#]".
std::string bar(const std::vector<bool>& bins);
/// \brief An HDR sweep's bins whose highlight clipped at every exposure, by their angle.
std::string clippedBinsLine(const control::SweepView& sweep);
/// \brief A session reply (`session new/show/resume`): its slices and any journal damage.
void printSessionReply(std::ostream& out, const nlohmann::json& reply);
/// \brief The status reply, every part a person acts on.
void printStatus(std::ostream& out, const nlohmann::json& reply);
/// \brief control::statusFields() as help text: one key a line, its meaning wrapped beside it.
std::string statusFieldsText();

}  // namespace slicecap::cli
