// Runs the `slicecap` command line in-process and keeps its exit code and both streams.
#pragma once

#include <sstream>
#include <string>
#include <vector>

#include "slicecap/cli/cli.hpp"

namespace slicecap::test {

struct CliResult {
  int code;
  std::string out, err;
};

inline CliResult runSlicecap(const std::vector<std::string>& args) {
  std::ostringstream out, err;
  const int code = cli::runCli(args, out, err);
  return {code, out.str(), err.str()};
}

}  // namespace slicecap::test
