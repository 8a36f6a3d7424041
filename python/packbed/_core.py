"""The implementation of packbed's Python API.

``packbed/__init__.py`` re-exports the public names (its ``__all__``), so the
package's namespace holds the API alone; the helpers, and the modules they
use (``json``, ``numpy``, ``os``, the typing names), stay here.
"""

from __future__ import annotations

import json
import os
import tempfile
import warnings
from pathlib import Path
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _packbed as _native
from ._packbed import ConfigError, ImpossibleError, SettingError
from ._progress import ProgressLike, _Progress

PathLike = Union[str, "os.PathLike[str]"]
ConfigLike = Union[None, PathLike, Mapping[str, Any]]


# ---------------------------------------------------------------- arguments


class PackbedWarning(UserWarning):
    """A result was written, but something in it needs a look: the warnings
    ``packbed`` prints on stderr (a compaction cut short by its step budget,
    sizes far from those requested, replicates of an ensemble that warned).
    The same texts are under ``warnings`` in ``summary.json``."""


def _warn(texts: Iterable[str]) -> None:
    # stacklevel 3: the warning points at the user's call of deposit/ensemble/merge.
    for text in texts:
        warnings.warn(text, PackbedWarning, stacklevel=3)


def _plain(value: Any) -> Any:
    """numpy scalars and arrays as Python numbers and lists, for JSON."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    raise ConfigError(f"config: a value of type {type(value).__name__} is not allowed: {value!r}")


def _json(value: Any, what: str) -> str:
    try:
        return json.dumps(value, default=_plain, allow_nan=False)
    except ValueError as e:
        raise ConfigError(f"{what}: {e}") from None


def _check_none(value: Any, where: str) -> None:
    """The TOML schema has no null: a None in a config dict is an error."""
    if value is None:
        raise ConfigError(f"config: {where} is None (leave the key out instead)")
    if isinstance(value, Mapping):
        for k, v in value.items():
            _check_none(v, f"{where}.{k}" if where else str(k))
    elif isinstance(value, (list, tuple)):
        for k, v in enumerate(value):
            _check_none(v, f"{where}[{k}]")


def _whole(name: str, value: Any, *, minimum: int = 1, optional: bool = False) -> Optional[int]:
    """A whole number argument, or a SettingError naming it."""
    if value is None and optional:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise SettingError(f"{name}: must be a whole number, got {value!r}")
    if value < minimum:
        raise SettingError(f"{name}: must be at least {minimum}, got {value}")
    if value >= 2**63:
        raise SettingError(f"{name}: must be below 2^63, got {value}")
    return int(value)


def _path(name: str, value: Any) -> str:
    if not isinstance(value, (str, os.PathLike)):
        raise SettingError(f"{name}: must be a path, got {value!r}")
    return os.fspath(value)


def _keywords(**given: Any) -> Optional[str]:
    """The command's overrides given as keywords (None ones left out), as JSON."""
    chosen = {k: v for k, v in given.items() if v is not None}
    for k in ("radii", "ratio"):
        if k in chosen and isinstance(chosen[k], (int, float, np.integer, np.floating)) and not isinstance(chosen[k], bool):
            chosen[k] = [chosen[k]]
    if isinstance(chosen.get("measures"), str):
        chosen["measures"] = [m.strip() for m in chosen["measures"].split(",")]
    return _json(chosen, "keywords") if chosen else None


def resolve_config(config: ConfigLike = None, **keywords: Any) -> Dict[str, Any]:
    """The full config a call would build, as a dict of the TOML schema.

    ``config`` is a TOML file's path, a dict of the TOML schema, or None (the
    default bed); ``keywords`` are the overrides of :func:`deposit`.
    """
    return json.loads(_resolve(config, keywords))


def _resolve(config: ConfigLike, keywords: Mapping[str, Any]) -> str:
    known = {"dim", "radii", "ratio", "beads", "box", "periodic", "count", "seed", "mode", "large", "measures"}
    unknown = sorted(set(keywords) - known)
    if unknown:
        raise ConfigError(
            f"unknown keyword `{unknown[0]}` (choose from {', '.join(sorted(known))})"
        )
    words = _keywords(**keywords)
    if config is None:
        return _native.resolve_config(None, None, words)
    if isinstance(config, Mapping):
        _check_none(config, "")
        return _native.resolve_config(None, _json(dict(config), "config"), words)
    if isinstance(config, (str, os.PathLike)):
        return _native.resolve_config(os.fspath(config), None, words)
    raise ConfigError(f"config: give a TOML file's path or a dict, got {type(config).__name__}")


# ---------------------------------------------------------------- beds


class Bed:
    """A packed bed: particles (spheres in 3D, discs in 2D) in a box.

    Made by :func:`deposit` (a built bed, with its run's summary) or
    :func:`read` (a bed file). The arrays share the bed's memory where the
    library's layout allows (``radii``, ``species``, ``body``: read-only
    views); ``positions`` is one copy.
    """

    __slots__ = ("_bed",)

    def __init__(self, native: Any) -> None:
        self._bed = native

    def __len__(self) -> int:
        return len(self._bed)

    def __repr__(self) -> str:
        b = self.box
        size = " x ".join(f"{b[k]:g}" for k in ("width", "depth", "height") if k in b)
        kind = "periodic" if b["periodic"] else "walled"
        return f"<packbed.Bed {self.dim}D, {len(self)} particles, box {size} ({kind})>"

    @property
    def dim(self) -> int:
        """2 (discs) or 3 (spheres)."""
        return self._bed.dim

    @property
    def positions(self) -> np.ndarray:
        """Particle centres, float64 array of shape (N, dim): x, y[, z]."""
        return self._bed.positions

    @property
    def radii(self) -> np.ndarray:
        """Radius of each particle, float64 array of shape (N,), read-only."""
        return self._bed.radii

    @property
    def species(self) -> np.ndarray:
        """Species index of each particle, uint32 array of shape (N,), read-only."""
        return self._bed.species

    @property
    def body(self) -> np.ndarray:
        """Body index of each particle (a chain's beads share one), uint32 (N,), read-only."""
        return self._bed.body

    @property
    def feed(self) -> Optional[np.ndarray]:
        """The feed of each particle (``[[feeds]]``: the ``feed`` column of
        ``particles.csv``), uint32 (N,); None for a bed of one feed."""
        return self._bed.feed

    @property
    def box(self) -> Dict[str, Any]:
        """The box: ``width``, ``depth`` (3D), ``height``, ``periodic``."""
        return self._bed.box

    @property
    def summary(self) -> Optional[Dict[str, Any]]:
        """The ``summary.json`` of the run that built the bed (None for a read bed)."""
        text = self._bed.summary_json
        return None if text is None else json.loads(text)

    def analyze(self, *, progress: ProgressLike = None, **options: Any) -> Dict[str, Any]:
        """The measures of the bed, as ``summary.json`` has them.

        ``options`` are keys of a config's ``[analysis]`` table
        (``contact_tol``, ``large_radius``, ``bulk_min_bodies``,
        ``chain_angle_from``, ``measures``); a built bed's own config gives
        the rest. Returns a dict with ``packing``, ``coordination``,
        ``percolation``, ``voids``, ``orientation``, ``segregation`` (those
        asked for) and ``measures_left_out``.
        """
        with _Progress(progress, "") as p:
            return json.loads(self._bed.analyze(_settings(options), p))

    def pores(self, *, progress: ProgressLike = None, **options: Any) -> Tuple["Any", "Any"]:
        """The pore network of the bed as two ``pandas.DataFrame``: pores and throats.

        The columns are those of ``pores.csv`` and ``throats.csv``: a pore's
        vertices (particle ids, and their image shifts on periodic beds), its
        power centre, volume, void volume, body radius, ``in_slab`` and its
        pressure under each axis' unit gradient; a throat's two pores, the
        image shift of the second, its constriction radius, conductance and
        flux per axis. ``options`` are keys of ``[analysis]`` (``flow`` for
        ``[analysis.flow]``: ``viscosity``, ``axes``, ``slab``, ``conductance``, ``conductance_factor``). Raises
        ``ImpossibleError`` when the bed has no bulk slab or its spheres
        overlap, with the reason.
        """
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("Bed.pores needs pandas: pip install pandas") from None
        chosen = dict(options)
        chosen.setdefault("measures", ["packing", "pores", "permeability"])
        with _Progress(progress, "") as p:
            _, pores, throats = self._bed.pores(_settings(chosen), p)
        return pd.DataFrame(pores), pd.DataFrame(throats)

    def drainage(self, *, progress: ProgressLike = None, **options: Any) -> Dict[str, Any]:
        """Primary drainage of the bed's pore network (docs/guide/drainage-and-drying.md).

        Returns a dict: ``summary`` (``summary.json``'s ``drainage``), and as
        ``pandas.DataFrame`` ``curve`` (the capillary pressure–saturation
        curve of ``drainage.csv``), ``relative`` (its rows with the relative
        permeabilities ``k_rw``, ``k_rg``, with the permeability measure),
        ``bridges`` (``liquid.csv``: the pendular bridges) and ``pores``
        (``pores.csv`` with ``liquid_state``, ``cluster``, ``liquid``).
        ``options`` are keys of ``[analysis]``; ``drainage`` for
        ``[analysis.drainage]`` (``surface_tension``, ``contact_angle``,
        ``trapping``, ``entry``, ``pressure``, ``reduced_pressure``,
        ``points``). Raises ``ImpossibleError`` when the bed has no drainage
        (no bulk slab, no outlet), with the reason.
        """
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("Bed.drainage needs pandas: pip install pandas") from None
        chosen = dict(options)
        chosen.setdefault("measures", ["packing", "permeability", "drainage"])
        with _Progress(progress, "") as p:
            text, curve, relative, bridges, pores = self._bed.drainage(_settings(chosen), p)
        summary = json.loads(text)
        return {
            "summary": summary.get("drainage"),
            "curve": pd.DataFrame(curve),
            "relative": pd.DataFrame(relative),
            "bridges": pd.DataFrame(bridges),
            "pores": pd.DataFrame(pores),
        }

    def agglomeration(self, *, progress: ProgressLike = None, **options: Any) -> Dict[str, Any]:
        """The drained cake dried: its solid bridges and agglomerates (docs/guide/drainage-and-drying.md,
        "Drying and agglomeration").

        Returns a dict: ``summary`` (``summary.json``'s ``agglomeration``),
        ``drainage`` (its ``drainage``, the state dried from), and as
        ``pandas.DataFrame`` ``bridges`` (``bridges.csv``; a missing neck or
        strength is NaN) and ``agglomerates`` (``agglomerates.csv``), and
        ``agglomerate_of`` (a numpy array: each particle's agglomerate, 0 for
        none). ``options`` are keys of ``[analysis]``; ``drying`` for
        ``[analysis.drying]`` (``concentration``, ``solubility``,
        ``crystal_density``, ``min_neck``, ``tensile_strength``) and
        ``drainage`` for ``[analysis.drainage]``. Raises ``ImpossibleError``
        when the bed has no drying (no bulk slab, no outlet), with the reason.
        """
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("Bed.agglomeration needs pandas: pip install pandas") from None
        chosen = dict(options)
        chosen.setdefault("measures", ["packing", "agglomeration"])
        with _Progress(progress, "") as p:
            text, bridges, groups, of = self._bed.agglomeration(_settings(chosen), p)
        summary = json.loads(text)
        return {
            "summary": summary.get("agglomeration"),
            "drainage": summary.get("drainage"),
            "bridges": pd.DataFrame(bridges),
            "agglomerates": pd.DataFrame(groups),
            "agglomerate_of": of,
        }

    def permeability(self, *, progress: ProgressLike = None, **options: Any) -> Dict[str, Any]:
        """The permeability of the bed's pore network, as ``summary.json``'s ``permeability``.

        ``k_x``, ``k_y`` (periodic beds) and ``k_z`` in length units²,
        ``k_over_d32_squared``, ``k_over_kozeny_carman``, ``anisotropy`` and
        each axis' flux and balance; ``options`` as for :meth:`pores`.
        Raises ``ImpossibleError`` when the bed has no pore space to measure.
        """
        chosen = dict(options)
        chosen.setdefault("measures", ["packing", "permeability"])
        with _Progress(progress, "") as p:
            text, _, _ = self._bed.pores(_settings(chosen), p)
        summary = json.loads(text)
        if summary.get("permeability") is None:
            raise ImpossibleError("permeability: " + str(summary.get("pores_note", "not computed")))
        return summary["permeability"]

    def cake(self, **options: Any) -> Dict[str, Any]:
        """The filter cake's properties, as ``summary.json``'s ``cake``.

        ``porosity``, ``d32``, ``specific_surface``, ``k_kozeny_carman``,
        ``height``, ``solids_per_area`` and ``whole`` (over the whole cake); with
        ``length_unit`` and ``solid_density`` (keys of ``[analysis]``, as
        ``options`` or from the bed's config) also ``k_kozeny_carman_m2``,
        ``solids_mass_per_area`` and ``specific_resistance`` in m/kg. A built
        bed without ``options`` gives its run's values.
        """
        summary = self.summary
        if summary is not None and not options and "cake" in summary:
            return summary["cake"]
        chosen = dict(options)
        chosen.setdefault("measures", ["packing"])
        measured = self.analyze(**chosen)
        if measured.get("cake") is None:
            raise ImpossibleError("cake: the bed has no bulk region to measure")
        return measured["cake"]

    def _summary_table(self, key: str, rows: str) -> "Any":
        """``summary.json``'s ``key.rows`` as a ``pandas.DataFrame``; ``None``
        for a bed without that key (read from a file, or not built so)."""
        summary = self.summary
        if summary is None or key not in summary:
            return None
        try:
            import pandas as pd
        except ImportError:
            raise ImportError(f"Bed.{key} needs pandas: pip install pandas") from None
        return pd.DataFrame(summary[key][rows])

    def psd(self) -> "Any":
        """The built bed's size distribution against the requested one, a ``pandas.DataFrame``.

        The rows of ``psd.csv``: ``radius``, ``diameter``, requested and placed
        mass and number percent passing. ``None`` for a bed read from a file or
        built without a size distribution.
        """
        return self._summary_table("psd", "table")

    def capture(self) -> "Any":
        """What the filter medium passed, held and left above it, a ``pandas.DataFrame``.

        The rows of ``capture.csv``, one per size class of the bodies fed after
        the medium: ``d_lo``, ``d_hi``, ``fed``, ``passed``, ``lodged``, ``cake``,
        ``grade_efficiency``. ``None`` for a bed built without a medium
        (``[[feeds]]`` with ``medium = true``) or read from a file. The totals,
        ``x50`` and the retention criteria: ``bed.summary["capture"]``.
        """
        return self._summary_table("capture", "classes")

    def constrictions(self) -> "Any":
        """The medium's constriction diameters beside the slurry's sizes, a ``pandas.DataFrame``.

        The rows of ``constrictions.csv``, one per class of one log-spaced
        axis over both: ``d_lo``, ``d_hi``, ``constrictions`` (the medium's
        throats in the class), ``constrictions_finer`` (the fraction of its
        throats narrower than ``d_hi``), ``slurry`` (bodies fed after the
        medium in the class), ``slurry_finer``. ``None`` for a bed built
        without a medium or read from a file; empty when the medium has no
        pore network. Its percentiles and the retention criteria:
        ``bed.summary["capture"]["criteria"]``.
        """
        return self._summary_table("capture", "constrictions")

    def filtration(self) -> "Any":
        """The filtration curve through medium and cake, a ``pandas.DataFrame``.

        The rows of ``filtration.csv``, one per checkpoint, SI: ``time_s``,
        ``volume_m3_per_m2``, ``pressure_pa``, ``cake_height_m``,
        ``mass_kg_per_m2``, ``r_total_per_m``, ``r_cake_per_m``,
        ``r_medium_per_m``. ``None`` for a bed built without a
        ``[filtration]`` table. Ruth's fitted α and R_m beside the network's:
        ``bed.summary["filtration"]``.
        """
        return self._summary_table("filtration", "checkpoints")

    def contacts(self, contact_tol: Optional[float] = None) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Particle–particle contacts: arrays ``i`` < ``j`` (uint32) and ``gap`` (float64).

        A contact is a pair of different bodies whose surface gap is at most
        ``contact_tol`` times the smaller radius (default: the analysis').
        """
        options = {} if contact_tol is None else {"contact_tol": contact_tol}
        return self._bed.contacts(_settings(options))

    def to_pandas(self) -> "Any":
        """The particles as a ``pandas.DataFrame`` with the columns of ``particles.csv``."""
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("Bed.to_pandas needs pandas: pip install pandas") from None
        columns = self._bed.columns.split(",")
        n = len(self)
        data: Dict[str, Any] = {"id": np.arange(n, dtype=np.int64)}
        data["species"] = np.asarray(self.species, dtype=np.int64)
        data["body"] = np.asarray(self.body, dtype=np.int64)
        pos = self.positions
        for k, axis in enumerate(columns[3 : 3 + self.dim]):
            data[axis] = pos[:, k]
        data["r"] = np.array(self.radii)
        feed = self._bed.feed
        if feed is not None:
            data["feed"] = np.asarray(feed, dtype=np.int64)
        return pd.DataFrame(data, columns=columns)

    def write(self, out: PathLike, *, pictures: bool = True, **analysis: Any) -> List[Path]:
        """Writes the bed's files into the folder ``out``, atomically.

        A built bed writes what ``packbed run`` writes; a read bed what
        ``packbed analyze`` writes (``analysis`` options as in
        :meth:`analyze`). Returns the paths written.
        """
        if analysis and self.summary is not None:
            raise ConfigError("write: a built bed writes its run's files; its config holds the analysis settings")
        files = self._bed.write(_path("out", out), _settings(analysis), bool(pictures))
        return [Path(f) for f in files]

    def fragment(
        self,
        *,
        load: str = "shear",
        breaks: Union[int, str] = "failure",
        kt_over_kn: float = 1.0,
        contact_tol: Optional[float] = None,
        out: Optional[PathLike] = None,
        pictures: bool = True,
        progress: ProgressLike = None,
    ) -> Dict[str, Any]:
        """Loads the bed's contact network and breaks its bonds (``packbed fragment``).

        ``load``: ``shear``, ``compression`` or ``gravity``; ``breaks``: a
        count of at least 1 or ``"failure"``; ``kt_over_kn``: tangential over
        normal stiffness; ``contact_tol``: as in :meth:`contacts` (default
        1e-9). Returns the ``summary.json`` of ``packbed fragment`` (its
        ``fragmentation`` key holds the measures); with ``out``, also writes
        ``bonds.csv``, ``breakage.csv``, the pictures and ``summary.json`` there.
        """
        options = {"load": load, "breaks": breaks, "kt_over_kn": kt_over_kn}
        tol = 1e-9 if contact_tol is None else contact_tol
        if isinstance(tol, bool) or not isinstance(tol, (int, float, np.integer, np.floating)):
            raise ConfigError(f"contact_tol: must be a number, got {tol!r}")
        target = None if out is None else _path("out", out)
        with _Progress(progress, "") as p:
            text = self._bed.fragment(_json(options, "fragment"), float(tol), target, bool(pictures), p)
        return json.loads(text)


def _settings(options: Mapping[str, Any]) -> str:
    chosen = dict(options)
    if isinstance(chosen.get("measures"), str):
        chosen["measures"] = [m.strip() for m in chosen["measures"].split(",")]
    _check_none(chosen, "")
    return _json(chosen, "analysis")


def deposit(
    config: ConfigLike = None,
    *,
    dim: Optional[int] = None,
    radii: Union[None, float, Sequence[float]] = None,
    ratio: Union[None, float, Sequence[float]] = None,
    beads: Optional[int] = None,
    box: Union[None, str, Sequence[float]] = None,
    periodic: Optional[bool] = None,
    count: Optional[int] = None,
    seed: Optional[int] = None,
    mode: Optional[str] = None,
    large: Optional[float] = None,
    measures: Union[None, str, Sequence[str]] = None,
    progress: ProgressLike = None,
) -> Bed:
    """Builds and analyses one bed, as ``packbed run`` does.

    ``config``: a TOML file's path, a dict of the TOML schema, or None (the
    default bed: 3D, radii 20 and 10 in number ratio 1:1, seed 1, the source
    study's box). The keywords override it as the command's options do:
    ``dim`` (2 or 3), ``radii`` (one species per radius), ``ratio`` (number
    ratio per species), ``beads`` (rigid chains of N beads), ``box``
    (``"thesis"``, ``"W,H"``, ``"W,D,H"``, ``"diameters=N"``, or the sizes as
    numbers), ``periodic``, ``count`` (exactly N particles), ``seed``,
    ``mode`` (``"deposit"`` or ``"rsa"``), ``large`` (percolation threshold
    radius), ``measures`` (which measures to compute).

    The same settings and seed give the same bed as the command, bit for bit.
    """
    resolved = _resolve(
        config,
        dict(dim=dim, radii=radii, ratio=ratio, beads=beads, box=box, periodic=periodic,
             count=count, seed=seed, mode=mode, large=large, measures=measures),
    )
    with _Progress(progress, "particles") as p:
        bed = Bed(_native.deposit(resolved, p))
    _warn((bed.summary or {}).get("warnings", []))
    return bed


def read(path: PathLike, box: Union[None, str, Sequence[float]] = None, periodic: Optional[bool] = None) -> Bed:
    """Reads a bed file: every format ``packbed analyze`` reads.

    packbed's ``particles.csv`` (its box from the ``summary.json`` beside it),
    a plain ``x y [z] r`` table, a LAMMPS dump, extended XYZ, VTU. ``box``
    (``"W,H"``, ``"W,D,H"`` or the sizes) and ``periodic`` give the box of a
    file without one, and win over the file's.
    """
    size: Optional[List[float]] = None
    if box is not None:
        if isinstance(box, str):
            try:
                size = [float(v) for v in box.split(",")]
            except ValueError:
                raise ConfigError(f"box: give W,H or W,D,H, got {box!r}") from None
        else:
            try:
                size = [float(v) for v in box]
            except (TypeError, ValueError):
                raise ConfigError(f"box: give the sizes as numbers, got {box!r}") from None
    if periodic is not None and not isinstance(periodic, bool):
        raise ConfigError(f"periodic: must be True or False, got {periodic!r}")
    return Bed(_native.read(_path("path", path), size, periodic))


# ---------------------------------------------------------------- ensembles


def ensemble(
    config: ConfigLike = None,
    *,
    runs: int,
    jobs: Optional[int] = None,
    out: Optional[PathLike] = None,
    client: Any = None,
    pictures: bool = True,
    progress: ProgressLike = None,
    **overrides: Any,
) -> Dict[str, Any]:
    """Runs ``runs`` replicate beds and returns their statistics (``packbed ensemble``).

    ``config`` and ``overrides`` as in :func:`deposit`. Replicate ``i`` is
    seeded from the master seed alone, so the statistics do not depend on
    ``jobs`` (threads; default all cores) or on where the replicates ran.

    With ``out``, the files of ``packbed ensemble`` are written there (and a
    rerun into it resumes); without, they go to a temporary folder that is
    removed. With ``client`` (a ``dask.distributed.Client``), the replicates
    run as Dask tasks on its cluster (``jobs`` threads per task, default 1)
    and the files are byte-identical to a local run's.

    Returns ``ensemble.json`` as a dict; for a config with a ``[sweep]``, a
    dict from each sweep value's label to its ``ensemble.json``.
    """
    runs_n = _whole("runs", runs)
    jobs_n = _whole("jobs", jobs, optional=True)
    resolved = _resolve(config, overrides)
    with tempfile.TemporaryDirectory(prefix="packbed-ensemble-") as scratch:
        target = os.path.join(scratch, "out") if out is None else _path("out", out)
        if client is None:
            with _Progress(progress, "beds") as p:
                points, _files, warned = _native.ensemble(resolved, runs_n, target, jobs_n, None, bool(pictures), p)
        else:
            from ._dask import run_on

            if not (hasattr(client, "submit") and hasattr(client, "nthreads")):
                raise SettingError(f"client: give a dask.distributed.Client, got {type(client).__name__}")

            points, _files, warned = run_on(client, resolved, runs_n, target, jobs_n or 1, bool(pictures), progress)
        _warn(warned)
        return _statistics(points)


def merge(dirs: Iterable[PathLike], out: PathLike, *, pictures: bool = True) -> Dict[str, Any]:
    """Joins the output folders of ensemble shards (``packbed merge``) into ``out``.

    Returns the statistics as :func:`ensemble` does.
    """
    paths = [_path("dirs", d) for d in dirs]
    points, _files, warned = _native.merge(paths, _path("out", out), bool(pictures))
    _warn(warned)
    return _statistics(points)


def compare(*dirs: PathLike, out: Optional[PathLike] = None, pictures: bool = True) -> "Any":
    """Compares runs, ensembles or sweeps (``packbed compare``): a ``pandas.DataFrame``.

    One row per measure the groups share (the cake first): per group
    ``<name>.mean``, ``.sd``, ``.n``; per group after the first its
    ``.difference`` from the first, Welch's ``.t``, ``.df`` and ``.p``, and
    for a positive measure the ``.ratio`` of the means with its 95 %
    confidence interval (``.ratio_ci_low``, ``.ratio_ci_high``). Lengths are
    in the first group's unit when the groups name different ones.
    With ``out``, ``compare.md``, ``compare.csv``, ``compare.json`` and the plots go there;
    without, to a temporary folder that is removed.
    """
    try:
        import pandas as pd
    except ImportError:
        raise ImportError("compare needs pandas: pip install pandas") from None
    import io

    paths = [_path("dirs", d) for d in dirs]
    with tempfile.TemporaryDirectory(prefix="packbed-compare-") as scratch:
        target = os.path.join(scratch, "out") if out is None else _path("out", out)
        text, _files = _native.compare(paths, target, bool(pictures and out is not None))
    return pd.read_csv(io.StringIO(text), index_col="measure")


def _statistics(points: Sequence[Tuple[Optional[str], str]]) -> Dict[str, Any]:
    def load(d: str) -> Dict[str, Any]:
        with open(os.path.join(d, "ensemble.json"), encoding="utf-8") as f:
            return json.load(f)

    if len(points) == 1 and points[0][0] is None:
        return load(points[0][1])
    return {label: load(d) for label, d in points}
