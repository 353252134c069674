// The error lib/capture throws for input its pipeline, journal or store refuses.
#pragma once

#include "slicecap/core/error.hpp"

namespace slicecap::capture {

/// \brief Input lib/capture refuses: a journal record that does not read back, a sample that would
/// not replay, a light fit without enough references, a recording to process that does not fit; the
/// message names the field or file. Calibration and response fits keep their narrower errors
/// (CalibrationError, ResponseFitError).
class CaptureError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

}  // namespace slicecap::capture
