"""dxlemu: drive the dxlemu DYNAMIXEL bus emulator from Python (standard library only).

- `Emulator` (daemon.py): start `dxlemu run` on a temporary bus, wait until it is ready, stop it.
- `Control` (control.py): the control API: get/set items, conditions, faults, clock, stats.
- `Client`, `Port` (protocol.py): a minimal controller speaking DYNAMIXEL Protocol 2.0/1.0,
  FEETECH or Modbus RTU (modbus.py) over the emulator's pseudo-terminal.
- pytest_plugin.py: the `dxlemu` fixture (loaded by pytest once the package is installed;
  `pytest -p dxlemu.pytest_plugin` otherwise).

See docs/python.md.
"""
from .control import Control, ControlError
from .daemon import DaemonError, DaemonProcess, Emulator, PortInfo, find_binary
from .protocol import (BadPacket, Client, CommError, CommTimeout, ModbusException, Port, Reply,
                       Status)

__all__ = ["BadPacket", "Client", "CommError", "CommTimeout", "Control", "ControlError",
           "DaemonError", "DaemonProcess", "Emulator", "ModbusException", "Port", "PortInfo",
           "Reply", "Status", "find_binary"]
