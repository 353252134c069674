// Writes the shared interpolation test vectors (grid_interpolation.json) from the C++ code.
#include <fstream>
#include <iostream>

#include "grid_interpolation_vectors.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_grid_interpolation_vectors OUT.json\n";
    return 2;
  }
  std::ofstream file(argv[1]);
  file << slicecap::vectors::build().dump(1) << "\n";
  if (!file) {
    std::cerr << "make_grid_interpolation_vectors: cannot write " << argv[1] << "\n";
    return 1;
  }
  return 0;
}
