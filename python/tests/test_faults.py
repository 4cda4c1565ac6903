"""Fault rules through the control client (docs/control-api.md, fault.*): added, listed with
their counters, removed. A daemon without the fault commands fails them."""
import pytest

from dxlemu import BadPacket, ControlError
from dxlemu.protocol import READ, CommTimeout

PRESENT_POSITION = 132

# Manual timing: replies go out at once and are never dropped as late on a loaded machine, and
# nothing moves or cools unless a test steps the clock. (The fixture's default is fast timing.)
pytestmark = pytest.mark.dxlemu(timing="manual")


@pytest.fixture
def control(dxlemu):
    """The fixture's control client."""
    return dxlemu.control


def test_a_rule_is_listed_with_its_counters_and_removed(dxlemu, control):
    rule = control.fault_add({"action": "drop_reply", "match": {"port": "dxl0", "servos": [2]},
                              "count": 1})
    with dxlemu.client() as client:
        client.send(2, READ, bytes([PRESENT_POSITION, 0, 4, 0]))
        with pytest.raises(CommTimeout):
            client.receive(2, timeout=0.2)
        assert client.read(2, PRESENT_POSITION, 4).value == 2048  # count 1: only once
        assert client.read(1, PRESENT_POSITION, 4).value == 2048  # servo 1 never matched
    (entry,) = control.fault_list()
    assert entry["id"] == rule and entry["rule"]["action"] == "drop_reply"
    assert entry["fired"] == 1
    control.fault_remove(rule)
    assert control.fault_list() == []
    with pytest.raises(ControlError):
        control.fault_remove(rule)


def test_corrupt_crc_makes_bad_packets_until_the_rules_are_cleared(dxlemu, control):
    control.fault_add({"action": "corrupt_crc", "match": {"port": "dxl0"}})
    with dxlemu.client() as client:
        with pytest.raises(BadPacket):
            client.ping(1)
        control.fault_clear()
        assert client.ping(1).error == 0


def test_a_bad_rule_is_refused_with_a_message(control):
    with pytest.raises(ControlError, match="rule/action: must be one of"):
        control.fault_add({"action": "explode"})
