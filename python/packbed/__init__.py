"""packbed: packed beds of spheres and discs, built the way a filter cake forms.

Particles settle one at a time under gravity into a box, fall, roll and come
to rest on the bed already there (exact geometry, deterministic for a seed);
every bed is analysed: packing, coordination, percolation, voids, orientation,
segregation; its contact network can be loaded and broken.

This package wraps the Rust library (the same code as the ``packbed``
command); nothing is reimplemented in Python. The vocabulary is the
command's: ``packbed.deposit`` is ``packbed run``, ``packbed.read`` and
``Bed.analyze`` are ``packbed analyze``, ``packbed.ensemble`` is ``packbed
ensemble`` (optionally on a Dask cluster), ``Bed.fragment`` is ``packbed
fragment``.

Example::

    import packbed
    bed = packbed.deposit(dim=3, radii=[10, 20], seed=5)
    print(len(bed), bed.positions.shape)
    print(bed.analyze()["packing"]["bulk"])
    stats = packbed.ensemble(dim=2, radii=[10], count=200, runs=8)

Errors are ``ValueError`` subclasses (:class:`PackbedError` and below) with the
command's one-line messages; Ctrl-C stops a long call with ``KeyboardInterrupt``.
What the command prints as a warning (a compaction cut short, sizes far from
those requested, replicates that warned) is a :class:`PackbedWarning`.
"""

from ._core import Bed, PackbedWarning, compare, deposit, ensemble, merge, read, resolve_config
from ._packbed import (
    ConfigError,
    DataError,
    FileError,
    ImpossibleError,
    PackbedError,
    SettingError,
    __version__,
)

# The public API. The package's namespace holds these names and nothing else
# public, as numpy's and pandas' do: the implementation, its helpers and the
# modules it imports live in private submodules (tests/test_api.py checks).
__all__ = [
    "Bed",
    "ConfigError",
    "DataError",
    "FileError",
    "ImpossibleError",
    "PackbedError",
    "PackbedWarning",
    "SettingError",
    "__version__",
    "compare",
    "deposit",
    "ensemble",
    "merge",
    "read",
    "resolve_config",
]
