// The `slicecap` command: a thin main over slicecap::cli.
#include <iostream>
#include <string>
#include <vector>

#include "slicecap/cli/cli.hpp"

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  return slicecap::cli::runCli(args, std::cout, std::cerr);
}
