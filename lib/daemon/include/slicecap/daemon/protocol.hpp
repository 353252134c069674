// The control protocol's names in the daemon's namespace: the daemon serves lib/control's protocol.
#pragma once

#include "slicecap/control/protocol.hpp"

namespace slicecap::daemon {

using control::Command;
using control::commandName;
using control::encodeError;
using control::encodeRequest;
using control::encodeResult;
using control::ErrorCode;
using control::errorCodeName;
using control::Export;
using control::Hello;
using control::kMaxRequestBytes;
using control::kProtocolVersion;
using control::parseRequest;
using control::Peer;
using control::ProtocolError;
using control::Reconstruct;
using control::Request;
using control::SessionDelete;
using control::SessionList;
using control::SessionNew;
using control::SessionResume;
using control::SessionShow;
using control::Status;
using control::SweepRedo;
using control::SweepStart;
using control::SweepStop;

}  // namespace slicecap::daemon
