"""cli.tools.keyboard: keys from terminal bytes, and when teleop publishes what (a fake clock)."""

from __future__ import annotations

from turtlectl.cli.tools.keyboard import PERIOD, RELEASE, Driver, Shown, keys, status_line
from turtlectl.messages import Twist


def test_arrows_wasd_space_and_q_are_read_from_what_the_terminal_sends():
    assert keys(b"\x1b[A\x1b[B\x1b[C\x1b[D") == ["up", "down", "right", "left"]
    assert keys(b"\x1bOA") == ["up"]  # application cursor mode
    assert keys(b"wasdW ") == ["up", "left", "down", "right", "up", "stop"]
    assert keys(b"q") == ["quit"] and keys(b"\x03") == ["quit"]
    assert keys(b"xyz\x1b[5~") == []  # other keys: nothing


def run(driver: Driver, presses: dict[float, str], until: float, step: float = 0.01) -> list[tuple[float, Twist]]:
    """Press keys at the given times and collect what is published, tick by tick."""
    sent = []
    t = 0.0
    while t <= until + 1e-9:
        key = presses.get(round(t, 2))
        if key is not None:
            driver.press(key, t)
        out = driver.tick(t)
        if out is not None:
            sent.append((round(t, 2), out))
        t = round(t + step, 2)
    return sent


def test_a_held_key_sends_its_command_at_the_period_and_a_release_sends_one_stop():
    driver = Driver(linear=2.0, angular=1.5)
    repeats = {round(0.05 * k, 2): "up" for k in range(21)}  # held for 1 s (auto-repeat every 50 ms)
    sent = run(driver, repeats, until=3.0)
    moving = [t for t, cmd in sent if cmd == Twist(linear=2.0)]
    gaps = [b - a for a, b in zip(moving, moving[1:], strict=False)]
    assert moving[0] == 0.0 and all(abs(gap - PERIOD) <= 0.011 for gap in gaps), moving  # ticks every 10 ms
    assert moving[-1] <= 1.0 + RELEASE
    stops = [t for t, cmd in sent if cmd == Twist()]
    assert len(stops) == 1 and 1.0 + RELEASE <= stops[0] <= 1.0 + RELEASE + 0.02  # released: one stop, then nothing
    assert sent[-1] == (stops[0], Twist()) and not driver.sending


def test_space_stops_at_once_and_keys_map_as_teleop_turtle_key():
    driver = Driver(linear=2.0, angular=1.5)
    sent = run(driver, {0.0: "left", 0.2: "stop"}, until=1.5)
    assert sent[0] == (0.0, Twist(angular=1.5)) and (0.2, Twist()) in sent and sent[-1] == (0.2, Twist())
    for key, twist in (("down", Twist(linear=-2.0)), ("right", Twist(angular=-1.5)), ("up", Twist(linear=2.0))):
        d = Driver(linear=2.0, angular=1.5)
        d.press(key, 0.0)
        assert d.tick(0.0) == twist


def test_a_new_key_goes_out_at_once_and_only_a_start_after_a_pause_counts_as_starting():
    driver = Driver(linear=1.0, angular=1.0)
    assert driver.press("up", 0.0) is True  # starts sending: the caller cancels a running goal
    assert driver.tick(0.0) == Twist(linear=1.0)
    assert driver.press("left", 0.03) is False  # already sending
    assert driver.tick(0.03) == Twist(angular=1.0)  # not a period later
    assert driver.tick(3.0) == Twist() and driver.tick(3.1) is None
    assert driver.press("up", 4.0) is True


def test_leaving_sends_a_stop_only_if_something_was_sent():
    driver = Driver(linear=1.0, angular=1.0)
    assert driver.halt() is None
    driver.press("up", 0.0)
    driver.tick(0.0)
    assert driver.halt() == Twist() and driver.halt() is None


def test_the_status_line_shows_the_command_and_the_pose():
    line = status_line(Shown(command=Twist(linear=2.0), pose=(1.0, 2.5, 90.0)))
    assert line == "sending linear +2.00 m/s angular +0.00 rad/s | x  1.00 y  2.50 heading  90.0 deg"
    assert status_line(Shown(command=Twist(), pose=None)).startswith("stopped | no pose yet")


def test_the_status_line_fits_the_terminal_so_redraws_never_wrap():
    """At 80 columns the line with a note fits (at 124 characters each redraw would leave a line)."""
    shown = Shown(command=Twist(linear=2.0), pose=(1.0, 2.5, 90.0), note="canceled the running goal (reason teleop)")
    for width in (200, 120, 80, 50, 30, 10):
        assert len(status_line(shown, width)) < width, width
    assert "canceled" in status_line(shown, 200) and status_line(shown, 80).startswith("sending linear +2.00")
    assert status_line(shown, 50) == "+2.00 m/s +0.00 rad/s | 1.00, 2.50, 90 deg"
