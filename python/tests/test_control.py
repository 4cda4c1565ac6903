"""The control client against the real daemon: each convenience method, errors, events."""
import pytest

from dxlemu import ControlError

# Manual timing: replies go out at once and are never dropped as late on a loaded machine, and
# nothing moves or cools unless a test steps the clock. (The fixture's default is fast timing.)
pytestmark = pytest.mark.dxlemu(timing="manual")


def test_get_and_set_an_item_and_raw_bytes(dxlemu):
    control = dxlemu.control
    assert control.set(2, "present_temperature", 70) == 70
    assert control.get(2, "present_temperature") == 70
    assert control.get(1, address=132, size=4) == 2048
    assert control.get(1, "id", port="dxl0") == 1


def test_list_and_stats_describe_the_bus(dxlemu):
    listing = dxlemu.control.list()
    assert [servo["id"] for servo in listing["ports"][0]["servos"]] == [1, 2, 3]
    assert dxlemu.control.stats()["dxl0"]["frames"] == 0
    assert "bad_checks" in dxlemu.control.stats("dxl0")["dxl0"]


def test_conditions_and_plugging(dxlemu):
    control = dxlemu.control
    assert control.condition_set(2, ambient_temperature=40)["ambient_temperature"] == 40.0
    assert control.detach(3) == {"attached": False, "booting": False}
    assert control.attach(3) == {"attached": True, "booting": True}
    assert control.power_cycle(1) == {"attached": True, "booting": True}
    assert control.reboot(2) == {"servo": 2, "attached": True, "booting": True}
    control.set(3, "led", 1)
    dxlemu.control.clock_step(ms=1000)
    assert control.factory_reset(3, keep="id")["servo"] == 3


def test_the_clock_is_stepped_in_manual_timing(dxlemu):
    assert dxlemu.control.clock_now() == 0
    assert dxlemu.control.clock_step(ms=250) == 250_000_000
    assert dxlemu.control.clock_now() == 250_000_000


def test_a_refused_request_raises_with_the_daemons_message_and_the_connection_stays(dxlemu):
    control = dxlemu.control
    with pytest.raises(ControlError, match="no servo 9 on dxl0"):
        control.get(9, "id")
    with pytest.raises(ControlError, match="unknown command"):
        control.call("gett")
    assert control.request("get", servo=1, item="id")["ok"]
    assert "help" in control.help()


def test_physics_methods_reach_the_daemon_which_says_it_has_no_world(dxlemu):
    # The default bus has no "physics": both commands are refused, by name, not as unknown.
    with pytest.raises(ControlError, match="physics: this daemon simulates no physics"):
        dxlemu.control.physics()
    with pytest.raises(ControlError, match="physics.apply: this daemon simulates no physics"):
        dxlemu.control.physics_apply(joint="shoulder", torque_nm=0.5)


def test_no_events_without_a_subscription(dxlemu):
    with dxlemu.client() as client:
        client.ping(1)  # traffic that a subscribed connection would get two events for
    assert dxlemu.control.get(1, "id") == 1  # events due would have come before this reply
    assert dxlemu.control.events() == []


def test_trace_events_are_kept_apart_from_replies(dxlemu):
    control = dxlemu.control
    control.trace_subscribe()
    with dxlemu.client() as client:
        client.ping(1)
    # A reply, although the Ping's two events came before it; they are kept for events().
    assert control.get(1, "id") == 1
    events = control.events()
    assert [(event["event"], event["dir"], event.get("packet")) for event in events] == [
        ("trace", "in", "id=1 ping"), ("trace", "out", "id=1 error=0x00 params=FC 03 2D")]
    control.trace_unsubscribe()


def test_hand_methods_move_a_joint_and_report_it(dxlemu):
    # The default bus names no joints: a hand takes a servo by its ID, degrees from 2048.
    control = dxlemu.control
    moved = control.hand_move(2, 90, duration_s=0.5)
    assert moved["joints"] == [{"joint": "2", "servo": 2}]
    control.clock_step(ms=600)
    assert control.get(2, "present_position") == 3072
    held = control.hand()
    assert [(h["servo"], h["source"], h["ended"]) for h in held] == [(2, "move", True)]
    swept = control.hand_sweep(joints=[1], to="middle")
    assert swept["joints"] == [{"joint": "1", "servo": 1}]
    assert len(control.hand_stop()["released"]) == 2
    with pytest.raises(ControlError, match="no such file|is no file"):
        control.hand_play("no-such-trajectory")
