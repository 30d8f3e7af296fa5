"""Keyboard driving for ``turtlectl teleop`` (pure: no zenoh, no terminal, no clock of its own).

``keys(data)`` turns what a terminal sends into key names (arrows, WASD, space, q);
``Driver`` decides what to publish when, as turtlesim's ``teleop_turtle_key`` does but
without a runaway turtle: a terminal reports presses, never releases, so a key counts as
held while it repeats (the terminal's auto-repeat) and as released ``release`` s after its
last repeat; then one stop command is sent and publishing stops.
"""

from __future__ import annotations

import msgspec

from turtlectl.messages import Twist

#: escape sequences of the arrow keys (normal and application cursor mode), and the WASD keys
ARROWS = {
    b"\x1b[A": "up",
    b"\x1b[B": "down",
    b"\x1b[C": "right",
    b"\x1b[D": "left",
    b"\x1bOA": "up",
    b"\x1bOB": "down",
    b"\x1bOC": "right",
    b"\x1bOD": "left",
}
LETTERS = {"w": "up", "s": "down", "a": "left", "d": "right", " ": "stop", "q": "quit", "\x03": "quit"}

#: s after the last repeat of a key at which it counts as released.  Terminals repeat a held
#: key after 250-660 ms, then every 30-50 ms: shorter would stutter at the start of a press.
RELEASE = 0.7
#: s between commands while a key is held (the simulator stops 1 s after the last one)
PERIOD = 0.1


def keys(data: bytes) -> list[str]:
    """The key names in ``data`` (one read of the terminal, several keys possible); other
    bytes are skipped."""
    found: list[str] = []
    i = 0
    while i < len(data):
        seq = data[i : i + 3]
        if seq in ARROWS:
            found.append(ARROWS[seq])
            i += 3
            continue
        name = LETTERS.get(chr(data[i]).lower())
        if name is not None:
            found.append(name)
        i += 1
    return found


class Driver:
    """What to publish on ``turtle1/cmd_vel`` from key presses: ``linear`` m/s forward or back
    (up/down, w/s), ``angular`` rad/s to the left or right (left/right, a/d), counter-clockwise
    positive; space stops at once."""

    def __init__(self, linear: float, angular: float, release: float = RELEASE, period: float = PERIOD):
        self.moves = {
            "up": Twist(linear=linear),
            "down": Twist(linear=-linear),
            "left": Twist(angular=angular),
            "right": Twist(angular=-angular),
        }
        self.release = release
        self.period = period
        self.command = Twist()  # what is being sent (zero: nothing)
        self.sending = False
        self._last_press = 0.0
        self._next = 0.0
        self._stop_due = False

    def press(self, key: str, now: float) -> bool:
        """A key was pressed (or repeated) at ``now`` (s).  True when this starts sending after
        a pause: the caller then cancels a running goal, so navigator and keyboard never fight."""
        if key == "stop":
            if self.sending or self.command != Twist():
                self._stop_due = True
            self.sending, self.command = False, Twist()
            return False
        move = self.moves.get(key)
        if move is None:
            return False
        started = not self.sending
        if move != self.command:
            self._next = now  # a new command goes out at once
        self.command, self.sending, self._last_press = move, True, now
        return started

    def tick(self, now: float) -> Twist | None:
        """What to publish at ``now`` (s), or None: the command every ``period`` while its key is
        held, one zero Twist when it is released or stopped, then nothing."""
        if self.sending and now - self._last_press > self.release:
            self.sending, self.command, self._stop_due = False, Twist(), True
        if self._stop_due:
            self._stop_due = False
            return Twist()
        if self.sending and now >= self._next:
            self._next += self.period  # on a grid: no drift with the caller's polling
            if self._next <= now:
                self._next = now + self.period
            return self.command
        return None

    def halt(self) -> Twist | None:
        """Leaving: a zero Twist if anything was sent since the last stop, else None."""
        moving = self.sending or self._stop_due
        self.sending, self.command, self._stop_due = False, Twist(), False
        return Twist() if moving else None


class Shown(msgspec.Struct):
    """What teleop's status line shows."""

    command: Twist
    pose: tuple[float, float, float] | None  # x m, y m, heading degrees
    note: str = ""


def status_line(shown: Shown, width: int = 200) -> str:
    """One line of at most ``width`` - 1 characters (a full-width line would wrap, and each
    redraw would leave a line behind): the command being sent and the turtle's pose; the
    note, then the words, are dropped first where it does not fit."""
    c = shown.command
    if shown.pose is None:
        where, short_where = "no pose yet (is the sim running?)", "no pose yet"
    else:
        x, y, heading = shown.pose
        where = f"x {x:5.2f} y {y:5.2f} heading {heading:5.1f} deg"
        short_where = f"{x:.2f}, {y:.2f}, {heading:.0f} deg"
    if c == Twist():
        sending = short = "stopped"
    else:
        sending = f"sending linear {c.linear:+.2f} m/s angular {c.angular:+.2f} rad/s"
        short = f"{c.linear:+.2f} m/s {c.angular:+.2f} rad/s"
    note = f" | {shown.note}" if shown.note else ""
    lines = (
        f"{sending} | {where}{note}",
        f"{sending} | {where}",
        f"{sending} | {short_where}",
        f"{short} | {short_where}",
    )
    for line in lines:
        if len(line) < width:
            return line
    return line[: max(0, width - 1)]
