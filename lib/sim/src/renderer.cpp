// The virtual camera: per-pixel ray to the target plane, LED and ambient irradiance, the target's
// albedo raster, the material's BRDF on a grid over the window; then occluder, noise, encoding.
#include "slicecap/sim/renderer.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "slicecap/eval/metrics.hpp"
#include "slicecap/sim/patterned_material.hpp"
#include "slicecap/sim/sim_error.hpp"
#include "slicecap/vision/target_surface.hpp"
#include "window_grid.hpp"

namespace slicecap::sim {
namespace {

constexpr int kTexelFloats = 4;  // albedo r, g, b (the desk where off the sheet), window
constexpr float kInvPi = static_cast<float>(1.0 / std::numbers::pi);
constexpr double kArmAlbedo = 0.05;  // the light arm: black anodised aluminium
constexpr double kWallAlbedo = 0.3;  // what the camera sees above the horizon

UnitVector unit(const Eigen::Vector3d& v) {
  const Eigen::Vector3d n = v.normalized();
  return {n.x(), n.y(), n.z()};
}

// 8-bit sRGB code of every 16-bit linear level.
const std::vector<std::uint8_t>& srgbTable() {
  static const std::vector<std::uint8_t> table = [] {
    std::vector<std::uint8_t> t(65536);
    for (std::size_t i = 0; i < t.size(); ++i)
      t[i] = static_cast<std::uint8_t>(std::lround(eval::srgbEncode(i / 65535.0) * 255.0));
    return t;
  }();
  return table;
}

// A 32-bit integer hash (lowbias32): sensor noise from (seed, sample index) without a sequential
// generator, so that the encoding loop vectorises.
inline std::uint32_t hash32(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

// Sensor noise and encoding of one row: linear levels first (branch-free, vectorised), then the
// sRGB table. The noise is the sum of a hash's four bytes, centred and scaled to unit variance
// (Irwin-Hall: near-normal, bounded at +-3.5 sigma, plenty for shot and read noise).
// [0, 1] as minss/maxss.
inline float clampUnit(float v) {
  return std::min(std::max(v, 0.0f), 1.0f);
}

// x86-64's baseline is SSE2 (4 floats a step); the noise loop is half the frame's time, so on a
// CPU with AVX2 (8 a step) a second copy is chosen at load time. The Pi's NEON build is unchanged.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define SLICECAP_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define SLICECAP_VECTOR_CLONES
#endif

SLICECAP_VECTOR_CLONES
void encodeRowNoisy(const float* row, int count, std::uint32_t rowSeed, float readNoise2,
                    float perFullWell, std::uint16_t* out) {
  constexpr float kInvByteSumSd = 1.0f / 147.8006f;  // sqrt(4 * (256^2 - 1) / 12)
  for (int i = 0; i < count; ++i) {
    float v = row[i];
    const std::uint32_t h = hash32(rowSeed + static_cast<std::uint32_t>(i));
    // Signed before float: SSE2 converts only signed integers without branches.
    const auto byteSum =
        static_cast<std::int32_t>((h & 255u) + ((h >> 8) & 255u) + ((h >> 16) & 255u) + (h >> 24));
    const float normal = (static_cast<float>(byteSum) - 510.0f) * kInvByteSumSd;
    v += std::sqrt(readNoise2 + clampUnit(v) * perFullWell) * normal;
    out[i] = static_cast<std::uint16_t>(static_cast<std::int32_t>(clampUnit(v) * 65535.0f + 0.5f));
  }
}

void encodeRowNoiseFree(const float* row, int count, std::uint16_t* out) {
  for (int i = 0; i < count; ++i)
    out[i] =
        static_cast<std::uint16_t>(static_cast<std::int32_t>(clampUnit(row[i]) * 65535.0f + 0.5f));
}

// Pass 1 of a row, branch-free so that it vectorises: each pixel's point on the plane and its
// Lambertian radiance factor (irradiance x pixel scale / pi). Behind the camera (w <= 0) is the
// sky.
SLICECAP_VECTOR_CLONES
void mapRowToPlane(const Eigen::Matrix3f& h, const float* ray, int width, float lx, float ly,
                   float lz, float ambient, float ledPart, float lambertScale, float* planeX,
                   float* planeY, float* lambertOf) {
  const float h00 = h(0, 0), h01 = h(0, 1), h02 = h(0, 2), h10 = h(1, 0), h11 = h(1, 1),
              h12 = h(1, 2);
  const float h20 = h(2, 0), h21 = h(2, 1), h22 = h(2, 2);
  for (int px = 0; px < width; ++px) {
    const float xn = ray[2 * px], yn = ray[2 * px + 1];
    const float w = h20 * xn + h21 * yn + h22;
    const float invW = 1.0f / w;
    const float x = (h00 * xn + h01 * yn + h02) * invW;
    const float y = (h10 * xn + h11 * yn + h12) * invW;
    const float dx = lx - x, dy = ly - y;
    const float d2 = dx * dx + dy * dy + lz * lz;
    planeX[px] = x;
    planeY[px] = y;
    lambertOf[px] = w > 0.0f ? (ambient + ledPart / (d2 * std::sqrt(d2))) * lambertScale : -1.0f;
  }
}

bool insideConvexQuad(const Occluder& q, double x, double y) {
  bool positive = false, negative = false;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d& a = q.cornersPx[i];
    const Eigen::Vector2d& b = q.cornersPx[(i + 1) % 4];
    const double cross = (b.x() - a.x()) * (y - a.y()) - (b.y() - a.y()) * (x - a.x());
    positive |= cross > 0;
    negative |= cross < 0;
  }
  return !(positive && negative);
}

// The target raster's values (albedo r, g, b, window) at texel coordinates (tx, ty), bilinear
// between its four nearest texels.
inline void sampleTexel(const float* texels, int texWidth, float tx, float ty, float* texel) {
  const int ix = static_cast<int>(tx), iy = static_cast<int>(ty);
  const float fx = tx - ix, fy = ty - iy;
  const float w00 = (1 - fx) * (1 - fy), w10 = fx * (1 - fy), w01 = (1 - fx) * fy, w11 = fx * fy;
  const float* t00 = &texels[kTexelFloats * (std::size_t(iy) * texWidth + ix)];
  const float* t01 = t00 + kTexelFloats * texWidth;
  for (int c = 0; c < kTexelFloats; ++c)
    texel[c] =
        w00 * t00[c] + w10 * t00[c + kTexelFloats] + w01 * t01[c] + w11 * t01[c + kTexelFloats];
}

}  // namespace

FrameRenderer::FrameRenderer(vision::CameraModel camera, vision::TargetGeometry target,
                             std::shared_ptr<const models::ReflectanceModel> material,
                             const RigParams& rig, RenderSettings settings)
    : camera_(std::move(camera)),
      target_(std::move(target)),
      material_(std::move(material)),
      rig_(rig),
      settings_(settings) {
  std::string error;
  if (!camera_.isValid(&error)) throw SimError("camera: " + error);
  if (!material_) throw SimError("FrameRenderer: no material");
  pattern_ = dynamic_cast<const PatternedMaterial*>(material_.get());
  if (settings_.brdfGridNodes < 3 || settings_.brdfGridNodes % 2 == 0)
    throw SimError("FrameRenderer: the BRDF grid needs an odd node count >= 3");
  const int width = camera_.intrinsics.widthPx, height = camera_.intrinsics.heightPx;
  rays_.resize(std::size_t(width) * height * 2);
  const vision::CameraIntrinsics& k = camera_.intrinsics;
  for (int y = 0; y < height; ++y) {
    Eigen::Vector2d n((0 - k.cxPx) / k.fxPx, (y - k.cyPx) / k.fyPx);
    for (int x = 0; x < width; ++x) {
      n = camera_.undistort({(x - k.cxPx) / k.fxPx, (y - k.cyPx) / k.fyPx}, n);
      rays_[2 * (std::size_t(y) * width + x)] = static_cast<float>(n.x());
      rays_[2 * (std::size_t(y) * width + x) + 1] = static_cast<float>(n.y());
    }
  }
  // The raster reaches one texel past the sheet so that its edge is filtered like any other.
  const double margin = 1.0 / settings_.texelsPerMm;
  texArea_ = {target_.sheet.xMinMm - margin, target_.sheet.yMinMm - margin,
              target_.sheet.xMaxMm + margin, target_.sheet.yMaxMm + margin};
  const vision::TargetRaster raster =
      vision::rasterizeTarget(vision::TargetSurface(target_), texArea_, settings_.texelsPerMm, 4);
  texWidth_ = raster.width;
  texHeight_ = raster.height;
  texels_.resize(std::size_t(texWidth_) * texHeight_ * kTexelFloats);
  // The desk is folded into the albedo, so a texel is 16 bytes and off-raster pixels are desk.
  for (std::size_t i = 0; i < std::size_t(texWidth_) * texHeight_; ++i) {
    for (int c = 0; c < 3; ++c)
      texels_[kTexelFloats * i + c] =
          static_cast<float>(raster.albedo[3 * i + c] + rig_.deskAlbedo * (1.0 - raster.sheet[i]));
    texels_[kTexelFloats * i + 3] = raster.window[i];
  }
}

double FrameRenderer::pixelScale(const FrameScene& scene) const {
  return rig_.sensorResponse * scene.exposureUs * 1e-6 * scene.gain;
}

double FrameRenderer::ledIrradiance(const FrameScene& scene, const Eigen::Vector3d& pointMm) const {
  if (!scene.ledOn) return 0.0;
  const Eigen::Vector3d toLight = scene.lightMm - pointMm;
  const double distanceM = toLight.norm() * 1e-3;
  const double cosine = std::max(0.0, toLight.z() / toLight.norm());
  return rig_.ledIntensityWPerSr * cosine / (distanceM * distanceM);
}

PointRadiometry FrameRenderer::windowPoint(const FrameScene& scene,
                                           const Eigen::Vector3d& pointMm) const {
  const Eigen::Vector3d cameraMm = scene.exposurePoses.front().cameraCentreMm();
  const UnitVector toView = unit(cameraMm - pointMm);
  PointRadiometry r;
  r.ledIrradiance = ledIrradiance(scene, pointMm);
  r.brdf = pattern_ ? pattern_->evaluateAt(pointMm.x(), pointMm.y(), unit(scene.lightMm - pointMm),
                                           toView)
                    : material_->evaluate(unit(scene.lightMm - pointMm), toView);
  const Rgb ambient = material_->evaluate({0.0, 0.0, 1.0}, toView);
  r.expectedLinear =
      (r.brdf * r.ledIrradiance + ambient * rig_.ambientIrradiance) * pixelScale(scene);
  return r;
}

// Everything about one exposure pose that is the same for all its pixels.
struct FrameRenderer::PoseState {
  Eigen::Matrix3f imageToPlane;  // normalised image coordinates -> target plane (mm)
  // Window radiance x pixel scale at the BRDF grid's nodes; a patterned material's two
  // components one after the other.
  std::vector<float> grid;
  float nodeStepX = 0, nodeStepY = 0;
};

FrameRenderer::PoseState FrameRenderer::prepare(const vision::Pose& pose, const FrameScene& scene,
                                                double scale) const {
  PoseState state;
  Eigen::Matrix3d planeToImage;
  planeToImage << pose.rotation.col(0), pose.rotation.col(1), pose.translationMm;
  state.imageToPlane = planeToImage.inverse().cast<float>();
  // Window radiance (LED and ambient) at the nodes, already scaled to pixel values.
  const int nodes = settings_.brdfGridNodes;
  const vision::RectMm& window = target_.window;
  state.nodeStepX = static_cast<float>(window.widthMm() / (nodes - 1));
  state.nodeStepY = static_cast<float>(window.heightMm() / (nodes - 1));
  const int components = pattern_ ? 2 : 1;
  state.grid.resize(std::size_t(nodes) * nodes * 3 * components);
  const Eigen::Vector3d cameraMm = pose.cameraCentreMm();
  for (int k = 0; k < components; ++k) {
    const models::ReflectanceModel& material = pattern_ ? pattern_->component(k) : *material_;
    float* grid = &state.grid[std::size_t(k) * nodes * nodes * 3];
    for (int j = 0; j < nodes; ++j) {
      for (int i = 0; i < nodes; ++i) {
        const Eigen::Vector3d point(window.xMinMm + i * window.widthMm() / (nodes - 1),
                                    window.yMinMm + j * window.heightMm() / (nodes - 1), 0.0);
        const UnitVector toView = unit(cameraMm - point);
        Rgb radiance = material.evaluate({0.0, 0.0, 1.0}, toView) * rig_.ambientIrradiance;
        if (scene.ledOn && scene.lightMm.z() > 0.0)
          radiance +=
              material.evaluate(unit(scene.lightMm - point), toView) * ledIrradiance(scene, point);
        for (int c = 0; c < 3; ++c)
          grid[3 * (std::size_t(j) * nodes + i) + c] = static_cast<float>(radiance[c] * scale);
      }
    }
  }
  return state;
}

void FrameRenderer::accumulateRow(const PoseState& state, const FrameScene& scene, double scale,
                                  int row, float* out) const {
  const Eigen::Matrix3f& h = state.imageToPlane;
  const int nodes = settings_.brdfGridNodes;
  const float ledFactor = scene.ledOn ? static_cast<float>(rig_.ledIntensityWPerSr * 1e6) : 0.0f;
  const float lx = static_cast<float>(scene.lightMm.x()),
              ly = static_cast<float>(scene.lightMm.y());
  const float lz = static_cast<float>(scene.lightMm.z());
  const float ambient = static_cast<float>(rig_.ambientIrradiance);
  const float lambertScale = static_cast<float>(scale) * kInvPi;
  const float desk = static_cast<float>(rig_.deskAlbedo);
  const float sky = static_cast<float>(kWallAlbedo * rig_.ambientIrradiance * scale) * kInvPi;
  const float texX0 = static_cast<float>(texArea_.xMinMm),
              texY1 = static_cast<float>(texArea_.yMaxMm);
  const float tpm = static_cast<float>(settings_.texelsPerMm);
  const float winX0 = static_cast<float>(target_.window.xMinMm),
              winY0 = static_cast<float>(target_.window.yMinMm);
  const float maxNode = nodes - 1.0001f;
  const int width = camera_.intrinsics.widthPx;
  const float* ray = &rays_[2 * std::size_t(row) * width];
  thread_local std::vector<float> planeX, planeY, lambertOf;
  planeX.resize(width), planeY.resize(width), lambertOf.resize(width);
  const float ledPart = lz > 0.0f ? ledFactor * lz : 0.0f;
  mapRowToPlane(h, ray, width, lx, ly, lz, ambient, ledPart, lambertScale, planeX.data(),
                planeY.data(), lambertOf.data());
  const vision::CameraIntrinsics& k = camera_.intrinsics;
  const WindowGrid window{
      state.grid.data(),
      nodes,
      state.nodeStepX,
      state.nodeStepY,
      winX0,
      winY0,
      maxNode,
      pattern_,
      {h(0, 0), h(0, 1), h(0, 2), h(1, 0), h(1, 1), h(1, 2), h(2, 0), h(2, 1), h(2, 2)},
      static_cast<float>(1.0 / k.fxPx),
      static_cast<float>(1.0 / k.fyPx)};
  // Pass 2: the target's raster, the desk, the window's radiance.
  for (int px = 0; px < width; ++px, out += 3) {
    const float lambert = lambertOf[px];
    if (lambert < 0.0f) {  // above the horizon: a dim wall
      out[0] += sky, out[1] += sky, out[2] += sky;
      continue;
    }
    const float x = planeX[px], y = planeY[px];
    const float tx = (x - texX0) * tpm - 0.5f, ty = (texY1 - y) * tpm - 0.5f;
    if (!(tx >= 0.0f && ty >= 0.0f && tx < texWidth_ - 1 && ty < texHeight_ - 1)) {
      const float v = lambert * desk;
      out[0] += v, out[1] += v, out[2] += v;
      continue;
    }
    float texel[kTexelFloats];
    sampleTexel(texels_.data(), texWidth_, tx, ty, texel);
    for (int c = 0; c < 3; ++c)
      out[c] += lambert * texel[c];
    if (texel[3] > 0.0f)
      addWindowRadiance(window, x, y, ray[2 * px], ray[2 * px + 1], texel[3], out);
  }
}

template <typename RowSink>
void FrameRenderer::renderRows(const FrameScene& scene, RowSink&& sink) const {
  if (scene.exposurePoses.empty())
    throw SimError("FrameRenderer: a scene needs a pose");
  const double scale = pixelScale(scene) / static_cast<double>(scene.exposurePoses.size());
  std::vector<PoseState> states;
  for (const vision::Pose& pose : scene.exposurePoses)
    states.push_back(prepare(pose, scene, scale));
  const int width = camera_.intrinsics.widthPx, height = camera_.intrinsics.heightPx;
  // The light arm, a convex quad: pixels inside show its dark anodised surface in room light.
  const float arm = static_cast<float>(kArmAlbedo / std::numbers::pi * rig_.ambientIrradiance *
                                       pixelScale(scene));
  double armTop = height, armBottom = -1;
  if (scene.occluder) {
    for (const Eigen::Vector2d& c : scene.occluder->cornersPx)
      armTop = std::min(armTop, c.y()), armBottom = std::max(armBottom, c.y());
  }
  std::vector<float> row(std::size_t(width) * 3);
  for (int y = 0; y < height; ++y) {
    std::fill(row.begin(), row.end(), 0.0f);
    for (const PoseState& state : states)
      accumulateRow(state, scene, scale, y, row.data());
    if (scene.occluder && y >= armTop - 1 && y <= armBottom + 1) {
      for (int x = 0; x < width; ++x) {
        if (insideConvexQuad(*scene.occluder, x, y))
          row[3 * x] = row[3 * x + 1] = row[3 * x + 2] = arm;
      }
    }
    sink(y, row.data());
  }
}

std::vector<float> FrameRenderer::renderLinear(const FrameScene& scene) const {
  const int width = camera_.intrinsics.widthPx;
  std::vector<float> linear(std::size_t(width) * camera_.intrinsics.heightPx * 3);
  renderRows(scene, [&](int y, const float* row) {
    std::copy(row, row + 3 * width, &linear[3 * std::size_t(y) * width]);
  });
  return linear;
}

Image FrameRenderer::render(const FrameScene& scene) const {
  const int width = camera_.intrinsics.widthPx, height = camera_.intrinsics.heightPx;
  const bool srgb = rig_.encoding == PixelEncoding::Srgb8;
  Image image{width, height, 3, srgb ? 8 : 16,
              std::vector<std::uint16_t>(std::size_t(width) * height * 3)};
  const bool noisy = rig_.readNoise > 0.0 || rig_.fullWellElectrons > 0.0;
  // Variance in full-scale units: read noise squared plus the signal over the full well.
  const auto readNoise2 = static_cast<float>(rig_.readNoise * rig_.readNoise);
  const auto perFullWell =
      static_cast<float>(rig_.fullWellElectrons > 0.0 ? 1.0 / rig_.fullWellElectrons : 0.0);
  const auto frameSeed = static_cast<std::uint32_t>(scene.noiseSeed ^ (scene.noiseSeed >> 32));
  const std::vector<std::uint8_t>& toSrgb = srgbTable();
  renderRows(scene, [&](int y, const float* row) {
    std::uint16_t* out = &image.samples[3 * std::size_t(y) * width];
    const std::uint32_t rowSeed = hash32(frameSeed ^ hash32(static_cast<std::uint32_t>(y)));
    if (noisy)
      encodeRowNoisy(row, 3 * width, rowSeed, readNoise2, perFullWell, out);
    else
      encodeRowNoiseFree(row, 3 * width, out);
    if (srgb) {
      for (int i = 0; i < 3 * width; ++i)
        out[i] = toSrgb[out[i]];
    }
  });
  return image;
}

}  // namespace slicecap::sim
