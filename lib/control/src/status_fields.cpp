// What each key of the status reply holds: `slicecap status --help` prints it, scripts/gen-reference
// copies it into docs/reference/protocol.md, and tests/control/status_fields_test.cpp holds it equal
// to the keys toJson(StatusView) writes (reply_views.cpp), so a field cannot go undocumented.
#include "slicecap/control/reply_views.hpp"

namespace slicecap::control {

const std::vector<ReplyField>& statusFields() {
  static const std::vector<ReplyField> fields{
      {"session", "the current session as session.show gives it, without created, directory and "
                  "the journal's recovery figures (null: none)"},
      {"sweep", "the sweep being captured or paused, as the sweep commands give it (null: none)"},
      {"next", "what to do next: a slicecap command or a sentence"},
      {"isotropy", "the isotropy test once the four diagonal sweeps are complete: isotropic, "
                   "informative, axial_sweeps_needed, reason (or error)"},
      {"pass_again", "the bins of the session's swept slices to pass over again, slowly: left "
                     "empty, or next to a peak the window cells rise toward but none reached "
                     "(docs/method.md 9.5); while a sweep runs, the empty bins still ahead of it "
                     "are not named (absent: none)"},
      {"pass_again.slice", "the slice, as a sweep's slice (name, kind, theta_i, theta_v)"},
      {"pass_again.azimuth_deg", "the bin centre's slice parameter: light azimuth on an axial "
                                 "slice, view azimuth on a diagonal one"},
      {"pass_again.reason", "empty, or peak_not_reached"},
      {"cell_texture", "the texture verdict of each finished sweep whose frames carry window "
                       "cells: how the export's cell slices and the bins to pass again read them "
                       "(docs/method.md 9.4; absent: none)"},
      {"cell_texture.slice", "the slice, as a sweep's slice (name, kind, theta_i, theta_v)"},
      {"cell_texture.action", "as read (no texture), albedo-normalised (each cell divided by its "
                              "spot's albedo factor) or window centres (the cells not used)"},
      {"cell_texture.spread_percent",
       "how far the cells' albedo factors differ between positions beyond the scatter of "
       "frames, about in percent (null: too few frames clear of the noise)"},
      {"cell_texture.reason", "why that action, with the figures the rule compared"},
      {"error", "why the sweep last paused or the session's storage last failed (cleared when a "
                "sweep starts or stops)"},
      {"recording", "record_frames: the sweep's raw-frame recording"},
      {"recording.directory", "where its frames are written"},
      {"recording.frames_written", "frames written so far"},
      {"recording.frames_queued", "frames waiting for the writer"},
      {"recording.frames_dropped", "frames left out of the recording (the writer was behind)"},
      {"recording.error", "why the recording stopped (the sweep goes on)"},
      {"texture", "texture_resolution: the sweep's texture capture"},
      {"texture.directory", "the session's texture folder"},
      {"texture.resolution", "texels along the window's side"},
      {"texture.bins_filled", "azimuth bins of the slice with a texture frame"},
      {"texture.frames_stored", "texture frames of the slice kept"},
      {"texture.session_frames_stored", "texture frames of every slice kept"},
      {"texture.stored_mb", "the texture folder's size in MB"},
      {"texture.damaged_frames_removed", "damaged frames the store removed when it opened"},
      {"exposure", "the sweep start's exposure metering: what it locked, or that it runs"},
      {"hdr", "hdr_levels > 1: the live HDR cycle's exposures, or why the sweep takes one"},
      {"camera_frames", "a live camera: its frames in the sweep run (or the last one)"},
      {"camera_frames.delivered", "frames the camera delivered"},
      {"camera_frames.dropped", "frames it lost (gaps in its sequence numbers)"},
      {"camera_frames.led_pattern", "the LED strobe's pattern"},
      {"camera_frames.led_clean_fraction",
       "frames with one LED state over their rows of interest, of those judged"},
      {"camera_frames.timing", "how the frames' exposure times are known"},
      {"decoding", "how the sweep run's frames become linear light (docs/linear-light.md)"},
      {"decoding.decoding", "linear, srgb, measured-curve, ... or measuring (the bracket runs)"},
      {"decoding.note", "the response fit's summary, or why this decoding"},
      {"room_light", "the room light the sweep run's samples saw, each figure once known"},
      {"room_light.to_led", "its median ratio to the LED's light on the white references"},
      {"room_light.change", "its median change from one LED-off frame to the next, relative"},
      {"room_light.change_to_led", "change x to_led: the change as a fraction of the LED's light"},
      {"decoding_check", "whether the sweep run's 8-bit frames decode alike and stay above black, "
                         "each figure once known (docs/linear-light.md)"},
      {"decoding_check.black_reading",
       "median of the black patch read against the white references (1: decoded right)"},
      {"decoding_check.black_reading_step",
       "its mean step from a sample to the next frame's, relative: a tone curve stretched per "
       "frame steps it one way"},
      {"decoding_check.black_reading_step_sigmas", "that mean in its standard errors"},
      {"decoding_check.window_at_black_channel", "the window's channel with most pixels at code 0"},
      {"decoding_check.window_at_black",
       "that channel's median fraction of pixels at code 0 (near 1: a colour matrix took it below "
       "black)"},
      {"decoding_check.window_unlit_channel",
       "the window's channel whose LED light (window less room light) sits lowest against its "
       "own spread"},
      {"decoding_check.window_unlit",
       "that channel's fraction of the latest samples at or below 0"},
      {"decoding_check.window_unlit_at_zero", "its fraction exactly at 0 (the clip pinned it)"},
      {"decoding_check.window_unlit_sigmas",
       "its median in robust standard errors, negative below 0 (an honest dark channel's sits "
       "at or above 0; the refusal rule, docs/real-sensors.md \"Refused sweeps\": below -6, "
       "window_unlit_mean_sigmas below -3, or more than half exactly at 0)"},
      {"decoding_check.window_unlit_mean_sigmas",
       "from 8 samples: the mean of its samples within 5 robust standard deviations of the median "
       "(a highlight's left out), in its standard errors"},
      {"decoding_check.window_unlit_verdict",
       "what the rule makes of it: not judged (a RAW stream, fewer than 4 samples), kept, "
       "refused as the run ends, refused (the run ended; its samples set aside), only warned of "
       "(refuse_broken_decoding = false), or not refused as no session was open when the run "
       "began"},
      {"decoding_check.window_step_channel",
       "the window's channel whose light over the white references steps most from a sample to "
       "the next frame's"},
      {"decoding_check.window_step",
       "its mean step, relative and signed: a tone curve stretched per frame steps it one way"},
      {"decoding_check.window_step_sigmas", "that mean in its standard errors"},
      {"tuning_file", "the Raspberry Pi tuning file chosen for the camera (libcamera cameras)"},
      {"tuning_file.setting", "tuning_file in slicecapd.conf: auto, off or a path"},
      {"tuning_file.file", "the file the camera's IPA reads; null: the camera's own"},
      {"tuning_file.reason", "why that file"},
      {"warnings", "what the configuration, the camera, the strobe, the decoding, its checks or the "
                   "room light does wrong for a real capture, each naming what to do"},
  };
  return fields;
}

}  // namespace slicecap::control
