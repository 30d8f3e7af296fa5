"""A node module for the zygote's tests whose import never ends in time (a hung zygote)."""

import time

time.sleep(30)  # pacing: ok (the test ends the zygote long before)


def main() -> None:
    pass
