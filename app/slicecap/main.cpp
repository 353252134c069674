// The `slicecap` command: a thin main over slicecap::cli.
#include <iostream>
#include <string>
#include <vector>

#include "slicecap/cli/cli.hpp"

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  const int code = slicecap::cli::runCli(args, std::cout, std::cerr);
  // What a command prints is part of its result (a fit's conversion losses, a comparison's
  // figures): a standard output that could not take it (a full disk, /dev/full) is a failure.
  std::cout.flush();
  if (!std::cout && code == slicecap::cli::kExitOk) {
    std::cerr << "slicecap: standard output: write failed\n";
    return slicecap::cli::kExitFailure;
  }
  return code;
}
