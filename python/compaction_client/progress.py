"""The text progress bar of Client.wait: one line redrawn in place (carriage return)."""
import sys

WIDTH = 30  # characters of the bar


def line(sweep, elapsed):
    """`sweep 3 [###########-------------------] 4/12 done, 1 failed, 0:00:42` for a sweep as
    GET /sweeps/{id} answers it; finished jobs (succeeded, failed, cancelled) count as done."""
    c = sweep["counts"]
    total = c["total"]
    done = total - c["queued"] - c["running"]
    filled = WIDTH if total == 0 else WIDTH * done // total
    seconds = int(elapsed)
    text = "sweep %d [%s%s] %d/%d done, %d failed" % (
        sweep["id"], "#" * filled, "-" * (WIDTH - filled), done, total, c["failed"])
    if c["cancelled"]:
        text += ", %d cancelled" % c["cancelled"]
    return text + ", %d:%02d:%02d" % (seconds // 3600, seconds // 60 % 60, seconds % 60)


class Bar:
    """Writes each new line over the previous one on stderr (looked up at each write, so a
    redirected sys.stderr receives it); close() ends the line."""

    def __init__(self):
        self._last = None

    def show(self, sweep, elapsed):
        text = line(sweep, elapsed)
        if text != self._last:
            pad = " " * max(0, len(self._last or "") - len(text))
            sys.stderr.write("\r" + text + pad)
            sys.stderr.flush()
            self._last = text

    def close(self):
        if self._last is not None:
            sys.stderr.write("\n")
            sys.stderr.flush()
