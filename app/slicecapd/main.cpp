// slicecapd: the capture daemon on the box. Builds the devices, the capture pipeline and the
// reconstruction from /etc/slicecap/slicecapd.conf and runs the daemon (lib/daemon) until SIGTERM.
#include <iostream>
#include <string>
#include <vector>

#include "slicecapd_setup.hpp"

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  return slicecap::slicecapd::run(args, std::cout, std::cerr);
}
