#include "app/cli/ctl_command.hpp"

#include <chrono>
#include <cstdlib>
#include <iostream>
#include <stdexcept>

#include "app/cli/ctl_request.hpp"
#include "app/cli/exit_status.hpp"
#include "app/daemon/run_options.hpp"
#include "io/control_client.hpp"

namespace dxlemu::app {

int run_ctl(const CtlArguments& ctl) {
  try {
    const auto request = ctl_request(ctl.command, ctl.args);
    // Where `dxlemu run` puts its socket by default (the PID part aside).
    const auto dir = default_control_path().parent_path();
    const auto path = ctl_control_socket(ctl.control, std::getenv("DXLEMU_CONTROL"), dir,
                                         io::live_control_sockets);
    io::ControlClient client(path);
    const auto timeout = std::chrono::milliseconds(static_cast<std::int64_t>(ctl.timeout_s * 1e3));
    const auto outcome = ctl_outcome(client.call(request.dump(), timeout));
    std::cout << outcome.out;
    std::cerr << outcome.err;
    return outcome.exit_code;
  } catch (const std::invalid_argument& e) {
    std::cerr << "dxlemu ctl: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const io::ControlConnectError& e) {
    std::cerr << "dxlemu ctl: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "dxlemu ctl: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace dxlemu::app
