"""``packbed.ensemble(..., client=...)``: the replicates as Dask tasks.

The ensemble is cut into shards (replicates ``i`` with ``i mod M == K``, the
command's ``--shard K/M``); each task runs one shard into a scratch folder on
its worker and sends back the files it wrote (a few kB per replicate), so the
workers need no shared file system. The client writes them side by side and
joins them with the library's merge, which gives exactly the files of a
single local run: the statistics are folded in replicate order, whatever
shard or worker built a replicate.
"""

from __future__ import annotations

import os
import tempfile
from typing import Any, Dict, List, Optional, Tuple

from . import _packbed as _native

#: Shards per worker thread: enough to balance replicates of unequal cost.
SHARDS_PER_THREAD = 4


def shard_files(config_json: str, runs: int, index: int, count: int, jobs: int) -> Dict[str, bytes]:
    """Runs shard ``index``/``count`` of the ensemble; returns its files by relative path."""
    with tempfile.TemporaryDirectory(prefix="packbed-shard-") as scratch:
        out = os.path.join(scratch, "shard")
        _native.ensemble(config_json, runs, out, jobs, (index, count), False, None)
        files: Dict[str, bytes] = {}
        for root, _dirs, names in os.walk(out):
            for name in names:
                path = os.path.join(root, name)
                with open(path, "rb") as f:
                    files[os.path.relpath(path, out)] = f.read()
        return files


def run_on(
    client: Any,
    config_json: str,
    runs: int,
    out: str,
    jobs: int,
    pictures: bool,
    progress: Any,
) -> Tuple[List[Tuple[Optional[str], str]], List[str], List[str]]:
    """Runs the ensemble's shards on ``client``'s cluster and merges them into ``out``."""
    try:
        from distributed import as_completed
    except ImportError:
        raise ImportError("client= needs dask.distributed: pip install 'dask[distributed]'") from None
    from ._progress import _Progress

    threads = sum(client.nthreads().values()) or 1
    count = max(1, min(runs, SHARDS_PER_THREAD * threads))
    futures = [
        client.submit(shard_files, config_json, runs, k, count, jobs, pure=False)
        for k in range(count)
    ]
    try:
        with tempfile.TemporaryDirectory(prefix="packbed-dask-") as scratch, _Progress(progress, "shards") as bar:
            dirs: List[str] = []
            done = 0
            for future, files in as_completed(futures, with_results=True):
                k = futures.index(future)
                d = os.path.join(scratch, f"shard-{k:05d}")
                _write_files(d, files)
                dirs.append(d)
                done += 1
                bar(done, count)
            dirs.sort()
            return _native.merge(dirs, out, pictures)
    except BaseException:
        client.cancel(futures)
        raise


def _write_files(root: str, files: Dict[str, bytes]) -> None:
    for rel, data in files.items():
        path = os.path.join(root, rel)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "wb") as f:
            f.write(data)


