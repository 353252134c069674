// slicecapd.conf's documented defaults (slicecapd --print-config, docs/reference/slicecapd-conf.md).
#include "slicecap/daemon/config.hpp"

#include <string>

namespace slicecap::daemon {

namespace {

// slicecapd --print-config, one constant per group of keys; documentedDefaults() joins them with
// a blank line between groups.

// What the file is.
constexpr const char* kHeaderDefaults = R"(# slicecapd configuration. `key = value`; `#` starts a comment. Unknown keys are errors.
# The daemon checks every field when it starts and names the line of any mistake.
)";
// The camera, its frames and how they become linear light.
constexpr const char* kCameraDefaults = R"(# Camera: libcamera (Raspberry Pi camera modules), v4l2 (USB cameras), file (plays a recording
# or a simulated session) or model (the virtual rig in front of a model of a Pi camera: queued
# buffers, rolling shutter, late controls, the ISP's curve; for tests and demonstrations).
camera = libcamera
# libcamera camera id or /dev/videoN; empty takes the first camera found.
camera_device =
# With camera = file: the recording or simulated session folder to play.
camera_recording =
# With camera = file: how many times faster than recorded its frames come (the same frames, with
# their recorded timestamps; the tests play a simulated session at 4 to wait less).
camera_recording_speed = 1
# Frame size in pixels.
resolution = 1280x720
# Locked exposure (microseconds) and gain (the camera's own units: V4L2's gain control, libcamera's
# analogue gain). Empty exposure_us: each sweep start meters it with the LED on (the brightest
# 0.5 % of the image brought to 0.35 of full scale, about a second, at most 33.3 ms: a darker
# scene needs more gain) and locks it, with gain at its value here or the camera's default, for
# the sweep; `slicecap status` shows what was locked.
# Set exposure_us when a glossy material's highlight clips (frames rejected as window_clipped).
exposure_us =
gain =
# HDR (docs/method.md 9.3): 2 or 3 exposures alternated by blocks of LED pairs through a live
# sweep, merged per azimuth bin, for a sharp highlight that clips one exposure (a metal, a satin).
# The longest is the sweep's exposure above; each shorter one starts 16 x shorter, and the
# shortest is shortened 4 x more wherever the window still clips. 1: one exposure. Needs
# led_alternate = true and a camera that locks its exposure; the file camera plays a recording's
# own levels.
hdr_levels = 1
# Camera intrinsics and distortion (from `slicecap calibrate`); empty uses the sensor's nominal model.
calibration =
# The sensor's readout time, top row to bottom row, in microseconds (`slicecapd --check-hardware`
# measures it). Empty: the camera's line time where it reports one, else a whole frame period
# (safe, but it rejects more frames as led_transition).
readout_us =
# The mains frequency of the room's lights in Hz: 50, 60, or 0 (not pinned). Lamps on AC mains
# flicker at twice it (100 or 120 Hz). With 50 or 60 every frame lasts a whole number of flicker
# periods (40 ms = 4 x 10 ms at 50 Hz, 25 fps; 33.3 ms = 4 x 8.33 ms at 60 Hz, 30 fps): each row of
# an LED-off frame then saw the room light the same row of the LED-on frames saw, at any exposure,
# and it subtracts out. `slicecapd --check-hardware` measures the flicker.
mains_hz = 0
# An LED-on frame whose room light neither LED-off frame saw: the window's room light changed
# between them (by more than their noise and 5 % of the LED's light) while the nearer was taken
# more than this many mm of camera travel away, as when frames are dropped in a bright room with a
# glossy material. Such a frame is rejected (room_light_unseen) instead of interpolated. 0: off
# (the default: a rejected frame is a bin the table interpolates, which cost more than it saved on
# the simulated session); 15 where `slicecap status` shows a bright room and dropped frames
# (docs/real-sensors.md).
room_light_unseen_mm = 0
# The frames' noise, which the white-reference test allows for (an 8-bit frame's references near
# black disagree by noise alone): read noise as a fraction of full scale, and shot noise as the
# electrons a full-scale value stands for at gain 1. `slicecapd --check-hardware` measures both;
# the defaults are a small 8-bit camera module's.
sensor_read_noise = 0.002
sensor_full_well_electrons = 8000
# How 8-bit frames become linear light. auto: at each sweep start, right after the metering and
# with the LED on, a bracket of 8 exposures (x1/32 .. x4, about a second) of the target's white and
# black references measures the camera's response curve, and every frame of the sweep is decoded
# through it; a camera delivering linear 16-bit frames needs none. Hold the target still and in
# view meanwhile. A bracket that cannot be fitted (target not in view, clipping, a camera that
# cannot lock or report its exposure), or a curve that does not fit it (RMS residual above 4 %: a
# camera whose ISP changes its curve per frame, as a Pi's adaptive contrast does), falls back to
# sRGB, with a warning in `slicecap status` naming the camera and the figure. measured-curve: the
# same. srgb: no bracket; frames decoded as sRGB (only for
# a camera known to encode sRGB).
decoding = auto
# A sweep run whose 8-bit decoding is shown broken is refused as it ends: a window channel whose
# light from the LED sits below black: its median over the latest samples more than 6 standard
# errors below 0, their mean (from 8 samples, a highlight's left out) more than 3, or the light
# exactly 0 in more than half of them (the LED only adds light; a colour matrix that takes a
# saturated colour's weak channel below black loses it, which no decoding brings back; an
# honest dark channel scatters around a mean at or above 0). The run's samples and
# texture frames are set aside: kept in the session, used by no table or export; `slicecap status`
# and the export say so, and sweeping the slice again (after camera_raw or tuning_file is changed)
# or redoing it starts afresh. false: the sweep is only warned about and its samples count.
refuse_broken_decoding = true
)";
// The sensor's RAW stream.
constexpr const char* kCameraRawDefaults = R"(# The sensor's RAW (Bayer) stream, black level off and 2 x 2 binned into linear light (half the
# sensor mode's size: a camera module 3 asked for 1280x720 delivers 1152x648; calibrate at that
# size): auto takes it where the camera's validation grants a format slicecap decodes (10/12/16-
# bit, packed or not; a Pi 5 turns packed RAW into its lossy compressed format, so the unpacked
# 16-bit one is asked for and taken; the processed stream only when none is granted), on
# requires it, off never takes it (docs/real-sensors.md).
camera_raw = auto
# The Raspberry Pi tuning file of the processed path (camera_raw = off, or no RAW granted):
# auto sets slicecap's own for the camera module 3 (IMX708; /usr/share/slicecap/tuning/, for the
# Pi 4's or the Pi 5's ISP) with contrast enhancement, adaptive lens shading, the colour matrix
# and temporal denoise off, so one measured response curve holds for every frame; other sensors
# keep their own. off: the camera's own tuning file. A path: that file, checked at start-up (a
# file that cannot be read or is not a tuning file stops slicecapd, naming it). RAW frames
# bypass the ISP: no tuning file is set for them (docs/real-sensors.md).
tuning_file = auto
)";
// With camera = model: the virtual rig.
constexpr const char* kModelCameraDefaults = R"(# With camera = model: the material (any `slicecap simulate --material`), the rig (realistic:
# hand-held jitter, blur, occlusion, room light; ideal: none), seconds per sweep, the positions the
# hand rests at on the way round, the ISP's tone curve (imx708: the Pi camera module 3's tuning),
# the seed of the rig's and the sensor's randomness, and the RAW format its sensor offers (empty:
# none; SRGGB10_CSI2P: a Pi 4's camera module 3; taken as camera_raw says). The room light: its
# irradiance on the target as a fraction of the LED's face-on (0.1: a home's 100-150 lx against a
# 3 W LED's ~1000 lx at 30 cm; an office's 500 lx is half the LED), its flicker frequency (100:
# lamps on 50 Hz mains, 120 on 60 Hz, 0 steady) and depth ((max - min) / (max + min), IEEE 1789's
# percent flicker / 100: 0.1 a filament lamp's; magnetic-ballast tubes, cheap LED drivers 0.3-1).
# The Pi it stands for (pisp: a Pi 5, whose validation turns packed RAW into its lossy compressed
# format, so slicecap asks again for the unpacked one; vc4: a Pi 4), and its ISP as the Pi's
# tuning files set it (docs/real-sensors.md): the tone curve stretched per frame from the
# histogram (rpi.contrast ce_enable), the colour matrix (imx708: the tuning's at 4640 K, which
# over-saturates here: the model's sensor has no crosstalk for it to undo; identity),
# the stream (rgb, what slicecap takes on a Pi; rec709: YUV420 Rec.709 limited, a Pi's video
# stream; sycc: YUV420 full range), the Pi 5's temporal denoise (the previous frame's weight where
# a pixel moved less than its noise; 0 off; no effect on vc4), the timestamps' jitter, and which
# frames count an exposure lock (request: those whose request carried it, as libcamera counts;
# truth: those the sensor took with it).
model_material = satin-blue-45
model_rig = realistic
model_sweep_seconds = 8
model_positions = 32
model_tone_curve = imx708
model_seed = 7
model_raw =
model_room_light = 0.1
model_flicker_hz = 100
model_flicker_depth = 0.1
model_pipeline = pisp
model_adaptive_contrast = true
model_colour_matrix = identity
model_stream = rgb
model_temporal_denoise = 0.5
model_timestamp_jitter_us = 20
model_lock_counting = request
)";
// The LED.
constexpr const char* kLedDefaults = R"(# LED: the GPIO chip and line that drive the LED driver (never an LED straight on a pin; see
# firmware/README.md). The line by name (as `gpioinfo` lists it) or by offset.
led_chip = gpiochip0
led_line = GPIO17
led_active_low = false
# Switch the LED off in blocks of frames, so ambient light can be measured and removed. false: the
# LED stays on and no room light is removed (only for a dark room).
led_alternate = true
# Frames the LED holds each state (on, then off). Each switch is timed from the camera's
# timestamps to fall where no row of the window or the white references is being exposed; a frame
# it falls in anyway is rejected as led_transition. A camera that cannot say when it exposed
# needs 4 or more.
led_frames_per_state = 2
# How long either side of a switch a row's exposure is not trusted (GPIO call, driver, LED rise).
led_guard_us = 200
# With camera = file: the file the LED's changes are written to (empty: <storage>/led.log).
led_log =
)";
// The target and where sessions and recordings are kept.
constexpr const char* kStorageDefaults = R"(# The printed target: "default" (slicecap target's built-in one) or a target JSON file.
target = default
# Where sessions are kept (one folder each; samples are on disk before they are acknowledged).
storage = /var/lib/slicecap
# Also keep every raw frame of a sweep (LED on and off) as a recording in the session's folder,
# <storage>/<session>/recordings/<kind>-<theta_i>-<theta_v>, to re-process the session on a desktop
# (`slicecap capture-offline <session>/recordings`). A writer thread saves the PNGs; frames that
# arrive while 4 wait are left out of the recording (counted in `slicecap status`), never out of
# the sweep; a full disk stops the recording, not the sweep. About 1-3 MB a 720p frame.
record_frames = false
)";
// Texture (BTF) capture.
constexpr const char* kTextureDefaults = R"(# Texture (BTF) capture: with N > 0 every accepted frame's window is also rectified to N x N texels
# (64, 128 or 256 are typical; 0 switches it off) and kept per azimuth bin, at most
# texture_frames_per_bin frames a bin (those nearest its centre), in <storage>/<session>/texture.
# Disk: 8 slices x 24 bins x that many frames x N^2 x 6 bytes at most (N = 128, 5 frames: 94 MB);
# memory only the index. `slicecap export` copies it; `slicecap btf EXPORT/<id>-texture -o DIR`
# reconstructs the BTF (on the box or a desktop). A session keeps the resolution it started with.
texture_resolution = 0
texture_frames_per_bin = 5
)";
// The control socket.
constexpr const char* kSocketDefaults = R"(# The control socket, when systemd does not pass one (slicecapd.socket), and the group allowed to use it.
socket = /run/slicecap/slicecapd.sock
socket_group = slicecap
# A client that sends no request for this many seconds is closed (0: never), so connections left
# open cannot hold all 128 client slots. `slicecap status --watch` asks every --interval seconds.
client_idle_timeout_s = 300
)";

}  // namespace

std::string DaemonConfig::documentedDefaults() {
  std::string text;
  for (const char* group :
       {kHeaderDefaults, kCameraDefaults, kCameraRawDefaults, kModelCameraDefaults, kLedDefaults,
        kStorageDefaults, kTextureDefaults, kSocketDefaults})
    text += (text.empty() ? "" : "\n") + std::string(group);
  return text;
}

}  // namespace slicecap::daemon
