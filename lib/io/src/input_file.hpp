// What every reader of lib/io checks first: a directory given where a file is expected.
#pragma once

#include <filesystem>
#include <string>
#include <system_error>

#include "slicecap/io/io_error.hpp"

namespace slicecap::io {

/// \brief Throws IoError "PATH: is a directory, not EXPECTED" when `path` is a directory: a
/// std::ifstream opens one and then fails its first read with a message naming no file
/// ("basic_filebuf::underflow error reading the file: Is a directory", or just "read error").
inline void refuseDirectory(const std::filesystem::path& path, const std::string& expected) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
    throw IoError(path.string() + ": is a directory, not " + expected);
}

}  // namespace slicecap::io
