// Per-texel reconstruction of a captured texture: every texel's slice samples through Method B
// (or Method A with one shared factorisation, or the learned prior), on a pool of threads.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "slicecap/btf/btf_texture.hpp"
#include "slicecap/btf/slice_texture.hpp"
#include "slicecap/btf/texture_grid.hpp"
#include "slicecap/core/slice.hpp"
#include "slicecap/methods/method_id.hpp"
#include "slicecap/prior/prior_model.hpp"
#include "slicecap/prior/prior_reconstruction.hpp"
#include "slicecap/recon/method_b.hpp"

namespace slicecap::btf {

/// \brief The methods of the registry that reconstruct every texel: Method B (docs/method.md §4),
/// texel by texel; Method A (§5), one factorised RBF system, a texel row per matrix product; the
/// learned prior (§8), texel by texel at each texel's own directions (a texel some slice's frames
/// missed is still reconstructed from the rest).
inline constexpr std::array<methods::MethodId, 3> kTexelMethods{
    methods::MethodId::B, methods::MethodId::A, methods::MethodId::Prior};

/// \brief Options of the per-texel reconstruction.
struct BtfReconstructionParams {
  methods::MethodId method = methods::MethodId::B;  ///< one of kTexelMethods
  recon::MethodBParams methodB;  ///< isotropic and torus rule also apply to Method A
  /// \brief MethodId::Prior: the model (e.g. prior::defaultPriorModel()), which must outlive
  /// the call, and its options (an operator's "isotropic" is `prior.isotropicOnly`).
  const prior::PriorModel* priorModel = nullptr;
  prior::PriorParams prior;
  int threads = 0;  ///< 0: std::thread::hardware_concurrency()
};

/// \brief What the reconstruction did.
struct BtfReconstructionReport {
  std::size_t texels = 0;
  int threads = 0;
  /// \brief Texels whose samples could not give a table (e.g. a slice no frame saw them in):
  /// their tables are zero.
  std::size_t failedTexels = 0;
  std::string firstFailure;  ///< the first failed texel's reason, naming the texel
  /// \brief Method B line fits that fell back to the closed form, over all texels.
  std::size_t closedFormFits = 0;
  /// \brief MethodId::Prior: texels blended with Method B (little directional structure) and
  /// texels fitted with the anisotropy terms.
  std::size_t priorBlendedTexels = 0;
  std::size_t priorAnisotropicTexels = 0;
  double seconds = 0.0;
};

/// \brief One texel's slice samples: per slice every bin whose median is finite for the texel, at
/// the texel's own light and view directions (from its point to the bin's LED and camera).
SliceSet texelSlices(const TextureGrid& grid, const std::vector<SliceTexture>& slices, int column,
                     int row);

/// \brief Every texel reconstructed. Rows of texels are shared out among the threads.
/// Throws BtfError for a method not in kTexelMethods, invalid Method B or prior
/// options, or MethodId::Prior without a model.
BtfTexture reconstructBtf(const TextureGrid& grid, const std::vector<SliceTexture>& slices,
                          const BtfReconstructionParams& params = {},
                          BtfReconstructionReport* report = nullptr);

}  // namespace slicecap::btf
