"""examples/packbed.ipynb runs from top to bottom and draws its figures."""

from conftest import ROOT, optional


def test_example_notebook_runs():
    nbformat = optional("nbformat")
    nbclient = optional("nbclient")
    optional("matplotlib")
    optional("ipykernel")
    nb = nbformat.read(str(ROOT / "examples" / "packbed.ipynb"), as_version=4)
    nbclient.NotebookClient(nb, timeout=600, kernel_name="python3").execute()
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]
    assert not [o for o in outputs if o.get("output_type") == "error"]
    figures = [o for o in outputs if "image/png" in o.get("data", {})]
    assert len(figures) == 2, "the bed and the sweep plot"
