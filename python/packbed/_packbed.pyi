"""Type stubs of the native module `packbed._packbed` (crates/packbed-py).

Its functions take settings as JSON text of the TOML schema and are wrapped by
the public API in `packbed/__init__.py`; use that instead.
"""

from os import PathLike
from pathlib import Path
from typing import Any, Callable, List, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

class PackbedError(ValueError):
    """Base of packbed's errors (a ValueError)."""

class ConfigError(PackbedError):
    """The configuration (a TOML file, a dict or a keyword) is invalid."""

class DataError(PackbedError):
    """A data file (bed file, PSD table) has bad content."""

class FileError(PackbedError):
    """A file or folder could not be read or written."""

class SettingError(PackbedError):
    """A setting of the call (runs, jobs, out, ...) is wrong."""

class ImpossibleError(PackbedError):
    """The request cannot be carried out."""

_Progress = Optional[Callable[[int, int], Any]]
_Made = Tuple[List[Tuple[Optional[str], Path]], List[Path], List[str]]

class Bed:
    """A packed bed (see `packbed.Bed`)."""

    @property
    def dim(self) -> int: ...
    def __len__(self) -> int: ...
    @property
    def positions(self) -> npt.NDArray[np.float64]: ...
    @property
    def radii(self) -> npt.NDArray[np.float64]: ...
    @property
    def species(self) -> npt.NDArray[np.uint32]: ...
    @property
    def body(self) -> npt.NDArray[np.uint32]: ...
    @property
    def box(self) -> dict[str, Any]: ...
    @property
    def columns(self) -> str: ...
    @property
    def summary_json(self) -> Optional[str]: ...
    def analyze(self, settings_json: str, progress: _Progress = None) -> str: ...
    def pores(
        self, settings_json: str, progress: _Progress = None
    ) -> Tuple[str, dict[str, npt.NDArray[Any]], dict[str, npt.NDArray[Any]]]: ...
    def drainage(
        self, settings_json: str, progress: _Progress = None
    ) -> Tuple[
        str,
        dict[str, npt.NDArray[Any]],
        dict[str, npt.NDArray[Any]],
        dict[str, npt.NDArray[Any]],
        dict[str, npt.NDArray[Any]],
    ]: ...
    def agglomeration(
        self, settings_json: str, progress: _Progress = None
    ) -> Tuple[
        str,
        dict[str, npt.NDArray[Any]],
        dict[str, npt.NDArray[Any]],
        npt.NDArray[np.uint32],
    ]: ...
    def contacts(
        self, settings_json: str
    ) -> Tuple[npt.NDArray[np.uint32], npt.NDArray[np.uint32], npt.NDArray[np.float64]]: ...
    def write(self, out: Union[str, PathLike[str]], settings_json: str, pictures: bool = True) -> List[Path]: ...
    def fragment(
        self,
        options_json: str,
        contact_tol: float,
        out: Optional[Union[str, PathLike[str]]] = None,
        pictures: bool = True,
        progress: _Progress = None,
    ) -> str: ...

def resolve_config(
    path: Optional[str] = None, config_json: Optional[str] = None, keywords_json: Optional[str] = None
) -> str: ...
def deposit(config_json: str, progress: _Progress = None) -> Bed: ...
def read(path: Union[str, PathLike[str]], size: Optional[List[float]] = None, periodic: Optional[bool] = None) -> Bed: ...
def ensemble(
    config_json: str,
    runs: int,
    out: Union[str, PathLike[str]],
    jobs: Optional[int] = None,
    shard: Optional[Tuple[int, int]] = None,
    pictures: bool = True,
    progress: _Progress = None,
) -> _Made: ...
def merge(dirs: List[Union[str, PathLike[str]]], out: Union[str, PathLike[str]], pictures: bool = True) -> _Made: ...
def compare(
    dirs: List[Union[str, PathLike[str]]], out: Union[str, PathLike[str]], pictures: bool = True
) -> Tuple[str, List[str]]: ...
