"""The package's surface: docstrings on every public name, type stubs and
py.typed installed, progress bars through tqdm."""

import inspect
from pathlib import Path

import packbed
from conftest import optional


def test_every_public_name_has_a_docstring():
    missing = []
    for name in packbed.__all__:
        obj = getattr(packbed, name)
        if name == "__version__":
            continue
        if not (inspect.getdoc(obj) or "").strip():
            missing.append(name)
    for name, member in vars(packbed.Bed).items():
        if name.startswith("_"):
            continue
        if not (inspect.getdoc(member) or "").strip():
            missing.append(f"Bed.{name}")
    assert not missing, missing
    assert packbed.__doc__ and "import packbed" in packbed.__doc__


def test_the_namespace_holds_the_api_only():
    # The module itself, not only what dir() shows: its public names are
    # those of __all__ (the helpers and the modules they use are in
    # packbed._core), as numpy's and pandas' are.
    api = sorted(n for n in packbed.__all__ if not n.startswith("_"))
    assert [n for n in dir(packbed) if not n.startswith("_")] == api
    assert sorted(n for n in vars(packbed) if not n.startswith("_")) == api
    for private in ("json", "np", "os", "tempfile", "time", "Path", "Any", "Dict", "Union", "annotations", "PathLike"):
        assert not hasattr(packbed, private), private
    # Every name of __all__ is there, once, and `import *` gives exactly those.
    assert len(set(packbed.__all__)) == len(packbed.__all__)
    for name in packbed.__all__:
        assert hasattr(packbed, name), name
    star = {}
    exec("from packbed import *", star)
    assert sorted(n for n in star if n != "__builtins__") == sorted(packbed.__all__)


def test_type_information_is_installed():
    here = Path(packbed.__file__).parent
    assert (here / "py.typed").exists()
    assert (here / "_packbed.pyi").exists()
    stub = (here / "_packbed.pyi").read_text()
    for name in ("def deposit", "def read", "def ensemble", "def merge", "class Bed"):
        assert name in stub, name


def test_errors_are_value_errors():
    for cls in (packbed.ConfigError, packbed.DataError, packbed.FileError, packbed.SettingError, packbed.ImpossibleError):
        assert issubclass(cls, packbed.PackbedError)
        assert issubclass(cls, ValueError)


def test_tqdm_bar(capsys):
    optional("tqdm")
    bed = packbed.deposit(dim=2, radii=1, count=20000, box="500,500", periodic=True, progress=True)
    assert len(bed) == 20000
    err = capsys.readouterr().err
    assert "particles" in err
    stats = packbed.ensemble(dim=2, radii=10, count=30, runs=3, pictures=False, progress=True)
    assert stats["replicates"] == 3
