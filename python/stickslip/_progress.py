"""A stage's progress in Python: the extension hands each event of the stage's progress sink to
a callable — ``("start", what, total)``, ``("advance", n)``, ``("message", text)``,
``("finish",)``, ``("status", line)``, ``("note", line)`` — and :class:`Bar` draws them as a
tqdm-style bar (with ``tqdm.auto`` when tqdm is installed: a widget in a notebook), notes as
lines, on stderr."""

from __future__ import annotations

import sys
import time
from typing import Any, Optional


class Bar:
    """Draws a stage's progress (the events above) on stderr."""

    def __init__(self) -> None:
        self._tqdm: Any = None
        self._own: Optional[dict] = None
        try:
            from tqdm.auto import tqdm  # type: ignore[import-not-found]

            self._make = tqdm
        except ImportError:
            self._make = None

    def __call__(self, event: str, *args: Any) -> None:
        getattr(self, "_" + event)(*args)

    def _start(self, what: str, total: int) -> None:
        self._finish()
        if self._make is not None:
            self._tqdm = self._make(total=total, desc=what, unit=" realizations", file=sys.stderr)
        else:
            self._own = {"what": what, "total": total, "done": 0, "t0": time.monotonic(), "drawn": 0.0}
            self._draw(force=True)

    def _advance(self, n: int) -> None:
        if self._tqdm is not None:
            self._tqdm.update(n)
        elif self._own is not None:
            self._own["done"] += n
            self._draw()

    def _message(self, text: str) -> None:
        if self._tqdm is not None:
            self._tqdm.set_postfix_str(text)

    def _finish(self) -> None:
        if self._tqdm is not None:
            self._tqdm.close()
            self._tqdm = None
        if self._own is not None:
            self._draw(force=True)  # (the bar stays, complete, as tqdm's does)
            sys.stderr.write("\n")
            sys.stderr.flush()
            self._own = None

    def _status(self, line: str) -> None:
        sys.stderr.write("\r\x1b[K" + line)
        sys.stderr.flush()

    def _note(self, line: str) -> None:
        sys.stderr.write("\r\x1b[K" + line + "\n")
        sys.stderr.flush()

    def _draw(self, force: bool = False) -> None:
        s = self._own
        assert s is not None
        now = time.monotonic()
        if not force and now - s["drawn"] < 0.1:
            return
        s["drawn"] = now
        done, total = s["done"], max(s["total"], 1)
        filled = int(40 * min(done / total, 1.0))
        rate = done / max(now - s["t0"], 1e-9)
        eta = f"{(total - done) / rate:.0f} s" if rate > 0 else "?"
        sys.stderr.write(f"\r{s['what']} [{'#' * filled}{'.' * (40 - filled)}] {done}/{s['total']} realizations  {rate:.0f}/s  eta {eta}")
        sys.stderr.flush()
