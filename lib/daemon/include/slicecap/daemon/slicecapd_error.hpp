// The error lib/daemon throws for what it refuses outside the configuration file and a request.
#pragma once

#include "slicecap/core/error.hpp"

namespace slicecap::daemon {

/// \brief What lib/daemon refuses outside slicecapd.conf (ConfigError) and a client's request
/// (RequestError): a socket path it cannot listen on, an HDR cycle or bracket plan it cannot run, a
/// recording it cannot resume; the message names it.
class SlicecapdError : public slicecap::Error {
 public:
  using slicecap::Error::Error;
};

}  // namespace slicecap::daemon
