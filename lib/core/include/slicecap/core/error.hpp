// The one base of the errors slicecap's modules throw, so a caller can tell them from others.
#pragma once

#include <stdexcept>

namespace slicecap {

/// \brief What every module's own error derives from (hal::CameraError, io::IoError,
/// daemon::ConfigError, ...): a failure with a message that names the input or device and what
/// went wrong. Catch `slicecap::Error` for "slicecap refused or failed, and says why"; what() is
/// the module error's text unchanged. Programming errors and the standard library's own failures
/// (std::bad_alloc, std::filesystem::filesystem_error) are not slicecap::Errors.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// \brief Bad usage of a program's command line (`slicecap`, `slicecapd`): an unknown option, a
/// missing value, a wrong number of arguments. The programs print it with their usage and exit 2.
class UsageError : public Error {
 public:
  using Error::Error;
};

}  // namespace slicecap
