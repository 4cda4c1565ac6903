#pragma once

#include "control/request.hpp"

// The control API's trace subscription commands (docs/control-api.md).
namespace dxlemu::control {

/// trace.subscribe {"port"?}: this connection receives every packet of the port (or of every
/// port) as {"event":"trace",...} lines; the result lists the ports.
ordered_json trace_subscribe(Target& target, const Args& args);
/// trace.unsubscribe: this connection's trace events stop.
ordered_json trace_unsubscribe(Target& target, const Args& args);

}  // namespace dxlemu::control
