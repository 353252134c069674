// The target geometry and the camera model as JSON (`slicecap target --json`, recording.json).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "slicecap/vision/camera_model.hpp"
#include "slicecap/vision/target.hpp"

namespace slicecap::io {

/// \brief The target as JSON (docs/recording-format.md): units mm, the frame's convention, sheet,
/// window, paper and ink albedo, every marker's id, size and corners (AprilTag order), patches.
nlohmann::json targetToJson(const vision::TargetGeometry& target);

/// \brief Parses and checks a target (vision::findTargetProblem). Throws IoError as
/// "FILE: PATH.field: problem", where `file` and `path` say where `value` came from.
vision::TargetGeometry targetFromJson(const nlohmann::json& value, const std::string& file,
                                      const std::string& path = "");

/// \brief Writes targetToJson, pretty-printed. Throws IoError naming the path.
void writeTargetJson(const std::filesystem::path& path, const vision::TargetGeometry& target);
/// \brief Reads a file written by writeTargetJson. Throws IoError naming the path and field.
vision::TargetGeometry readTargetJson(const std::filesystem::path& path);

/// \brief {"width_px", "height_px", "fx_px", "fy_px", "cx_px", "cy_px", "distortion": {"model":
/// "opencv-radtan5", "k1", "k2", "p1", "p2", "k3"}}.
nlohmann::json cameraToJson(const vision::CameraModel& camera);
/// \brief The largest width_px or height_px cameraFromJson accepts (a 16k sensor; a camera module
/// is 4608 x 2592 at most).
inline constexpr int kMaxCameraSidePx = 16384;
/// \brief Parses and checks (CameraModel::isValid, sides up to kMaxCameraSidePx) a camera; errors
/// as targetFromJson.
vision::CameraModel cameraFromJson(const nlohmann::json& value, const std::string& file,
                                   const std::string& path = "");

/// \brief The deepest nesting of arrays and objects the JSON readers accept. slicecap's files nest
/// 6 deep at most; a deeper one is damaged, and printing one nested 30000 deep in an error message
/// (nlohmann's dump recurses) would overflow the stack.
inline constexpr int kMaxJsonDepth = 64;

/// \brief Parses a JSON file; IoError naming the path when it cannot be read or parsed (also a
/// number beyond a double, or nesting deeper than kMaxJsonDepth), or is a directory.
nlohmann::json readJsonFile(const std::filesystem::path& path);
/// \brief Parses JSON text as readJsonFile does; its IoError starts with `source` (what the text
/// is, e.g. a file's path).
nlohmann::json parseJson(std::string_view text, const std::string& source);
/// \brief Writes JSON (indent 1) through a temporary file and a rename, so a reader never sees a
/// half-written file. IoError naming the path.
void writeJsonFileAtomically(const std::filesystem::path& path, const nlohmann::json& value);

}  // namespace slicecap::io
