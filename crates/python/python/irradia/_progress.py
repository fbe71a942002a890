"""The progress bar of ``Scene.render(progress=True)``: a tqdm bar when tqdm can be
imported, else a warning once and no bar."""

import warnings

_warned = False


class _Bar:
    """Called with (done, total) pixel-samples from the thread that called render."""

    def __init__(self, tqdm):
        self._tqdm = tqdm
        self._bar = None

    def __call__(self, done, total):
        if self._bar is None:
            self._bar = self._tqdm(total=total, unit="px", unit_scale=True, desc="render")
        if total is not None and self._bar.total != total:
            self._bar.total = total
        self._bar.update(done - self._bar.n)

    def close(self):
        if self._bar is not None:
            self._bar.close()


def bar():
    """A tqdm-backed callback, or None when tqdm is not installed."""
    global _warned
    try:
        from tqdm.auto import tqdm
    except ImportError:
        if not _warned:
            warnings.warn("irradia: progress=True needs tqdm (pip install tqdm); rendering without a bar")
            _warned = True
        return None
    return _Bar(tqdm)
