// The texture grid's checks.
#include "slicecap/btf/texture_grid.hpp"

#include <stdexcept>
#include <string>

#include "slicecap/btf/btf_error.hpp"

namespace slicecap::btf {

TextureGrid::TextureGrid(int resolution, const vision::RectMm& window)
    : resolution_(resolution), window_(window) {
  if (resolution < 1 || resolution > 1024)
    throw BtfError("texture resolution must be 1 to 1024 texels across, not " +
                   std::to_string(resolution));
  if (!(window.widthMm() > 0 && window.heightMm() > 0))
    throw BtfError("texture grid: the target's window is not a rectangle");
}

}  // namespace slicecap::btf
