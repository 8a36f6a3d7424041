"""Progress of the native calls: the user's callable or a tqdm bar. Its own
module so that ``_core`` and ``_dask`` both use it without importing each
other."""

from __future__ import annotations

import time
from typing import Any, Callable, Union

from ._packbed import SettingError

#: ``None`` (a bar from ``tqdm`` if it is installed and the call lasts more
#: than a second), ``False`` (none), ``True`` (a bar, ``tqdm`` required) or a
#: callable ``f(done, total)`` (``total`` is 0 when unknown).
ProgressLike = Union[None, bool, Callable[[int, int], Any]]

#: Seconds a call runs before an automatic progress bar appears.
_BAR_AFTER = 1.0


class _Progress:
    """A ``f(done, total)`` for the native calls: the user's callable, or a
    tqdm bar made once the call has lasted a second (or at once if asked)."""

    def __init__(self, progress: ProgressLike, unit: str) -> None:
        if not (progress is None or isinstance(progress, bool) or callable(progress)):
            raise SettingError(f"progress: give None, True, False or a callable f(done, total), got {progress!r}")
        self._user = progress if callable(progress) and not isinstance(progress, bool) else None
        self._want = progress is None or progress is True
        self._force = progress is True
        self._unit = unit
        self._start = time.monotonic()
        self._bar: Any = None
        if self._force:
            from tqdm.auto import tqdm  # True asks for a bar: tqdm must be there

            self._bar = tqdm(unit=unit, leave=False)

    def __call__(self, done: int, total: int) -> None:
        if self._user is not None:
            self._user(done, total)
            return
        if not self._want:
            return
        if self._bar is None:
            if not self._force and time.monotonic() - self._start < _BAR_AFTER:
                return
            try:
                from tqdm.auto import tqdm
            except ImportError:
                self._want = False
                return
            self._bar = tqdm(total=total or None, unit=self._unit, leave=False)
        if total and self._bar.total != total:
            self._bar.total = total
        self._bar.update(done - self._bar.n)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    def __enter__(self) -> "_Progress":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()
