//! `Bed`: a bed built by `deposit` or read by `read`, its arrays as numpy
//! arrays that borrow the bed's memory (read-only; positions are one copy,
//! the library keeps them as points), and its analysis, contacts, files and
//! breakage through the library's front door.

use crate::config::load;
use crate::detached::{self, Shared};
use crate::errors::{config as config_error, to_py};
use numpy::ndarray::ArrayView1;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use packbed::particles_header;
use packbed::{AnalysisConfig, AnyBed, BoxHint, BoxSource, FinishedBed, ReadReport, RunExtras};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;

/// Where a bed came from, which decides what `write` writes.
enum Origin {
    /// Built by `deposit`: the files of `packbed run`.
    Built(Box<FinishedBed>),
    /// Read from a file: the files of `packbed analyze`.
    Read {
        bed: AnyBed,
        report: ReadReport,
        source: String,
    },
}

/// A packed bed of spheres (3D) or discs (2D).
#[pyclass(module = "packbed._packbed", frozen)]
pub struct Bed {
    origin: Origin,
}

impl Bed {
    fn bed(&self) -> &AnyBed {
        match &self.origin {
            Origin::Built(f) => &f.bed,
            Origin::Read { bed, .. } => bed,
        }
    }

    fn source(&self) -> (&str, ReadReport) {
        match &self.origin {
            Origin::Built(_) => (
                "packbed.deposit",
                ReadReport {
                    box_source: BoxSource::Built,
                    wrapped: 0,
                },
            ),
            Origin::Read { report, source, .. } => (source, *report),
        }
    }
}

/// A read-only numpy view of `data`, kept alive by the bed `owner`.
/// A table's columns as a dict of numpy arrays (what pandas builds a
/// DataFrame from).
fn columns_dict<'py>(
    py: Python<'py>,
    columns: Vec<(String, packbed::PoreColumn)>,
) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    for (name, column) in columns {
        match column {
            packbed::PoreColumn::Int(v) => out.set_item(name, PyArray1::from_vec(py, v))?,
            packbed::PoreColumn::Float(v) => out.set_item(name, PyArray1::from_vec(py, v))?,
        }
    }
    Ok(out)
}

fn view<'py, T: numpy::Element>(
    owner: &Bound<'py, Bed>,
    data: &[T],
) -> PyResult<Bound<'py, PyArray1<T>>> {
    // SAFETY: the bed is frozen (never mutated after construction) and the
    // array holds a reference to it, so `data` outlives the array unchanged.
    let array =
        unsafe { PyArray1::borrow_from_array(&ArrayView1::from(data), owner.clone().into_any()) };
    let flags = PyDict::new(owner.py());
    flags.set_item("write", false)?;
    array.call_method("setflags", (), Some(&flags))?;
    Ok(array)
}

#[pymethods]
impl Bed {
    /// 2 or 3.
    #[getter]
    fn dim(&self) -> u8 {
        self.bed().dim()
    }

    fn __len__(&self) -> usize {
        self.bed().len()
    }

    /// Particle centres, shape (N, dim), float64 (a fresh copy).
    #[getter]
    fn positions<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let this = slf.get();
        let dim = usize::from(this.bed().dim());
        let flat = PyArray1::from_vec(slf.py(), this.bed().positions());
        flat.reshape([this.bed().len(), dim])
    }

    /// Radii, shape (N,), float64, read-only, sharing the bed's memory.
    #[getter]
    fn radii<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        view(slf, slf.get().bed().radii())
    }

    /// Species index of each particle, shape (N,), uint32, read-only.
    #[getter]
    fn species<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray1<u32>>> {
        view(slf, slf.get().bed().species())
    }

    /// The feed of each particle (the `feed` column of `particles.csv`),
    /// uint32, for a bed built from `[[feeds]]`; None otherwise.
    #[getter]
    fn feed<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<u32>>> {
        self.bed().feeds().map(|f| PyArray1::from_vec(py, f))
    }

    /// Body index of each particle (the beads of a chain share it), uint32, read-only.
    #[getter]
    fn body<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray1<u32>>> {
        view(slf, slf.get().bed().bodies())
    }

    /// The box as a dict: width, [depth,] height, periodic.
    #[getter]
    #[pyo3(name = "box")]
    fn container<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let bed = self.bed();
        let size = bed.size();
        let d = PyDict::new(py);
        d.set_item("width", size[0])?;
        if size.len() == 3 {
            d.set_item("depth", size[1])?;
        }
        d.set_item("height", size[size.len() - 1])?;
        d.set_item("periodic", bed.periodic())?;
        Ok(d)
    }

    /// Column names of `particles.csv`, in order.
    #[getter]
    fn columns(&self) -> String {
        let header = match self.bed() {
            AnyBed::D2(_) => particles_header::<2>(),
            AnyBed::D3(_) => particles_header::<3>(),
        };
        match self.bed().feeds() {
            Some(_) => format!("{header},feed"),
            None => header.to_string(),
        }
    }

    /// The `summary.json` of the run that built the bed (JSON text), or None.
    #[getter]
    fn summary_json(&self) -> PyResult<Option<String>> {
        match &self.origin {
            Origin::Built(f) => f.summary.to_json().map(Some).map_err(to_py),
            Origin::Read { .. } => Ok(None),
        }
    }

    /// The measures (JSON text) with the analysis settings `settings_json`
    /// (the `[analysis]` table of a config as JSON; for a built bed, its
    /// config's table is the default).
    #[pyo3(signature = (settings_json, progress=None))]
    fn analyze(
        &self,
        py: Python<'_>,
        settings_json: &str,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<String> {
        let settings = self.settings(settings_json)?;
        let bed = self.bed();
        let (_, summary) = detached::run(py, progress, |_| {
            packbed::analyze_bed(bed, &settings).map_err(to_py)
        })?;
        serde_json::to_string(&summary).map_err(|e| config_error(e.to_string()))
    }

    /// The pore space with the analysis settings (`measures` given by the
    /// caller): the measures (JSON text) and the columns of `pores.csv` and
    /// `throats.csv` as dicts of numpy arrays; raises `ImpossibleError` with
    /// the reason when the bed has no pore space to measure.
    #[pyo3(signature = (settings_json, progress=None))]
    #[allow(clippy::type_complexity)]
    fn pores<'py>(
        &self,
        py: Python<'py>,
        settings_json: &str,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<(String, Bound<'py, PyDict>, Bound<'py, PyDict>)> {
        let settings = self.settings(settings_json)?;
        let bed = self.bed();
        let (_, summary) = detached::run(py, progress, |_| {
            packbed::analyze_bed(bed, &settings).map_err(to_py)
        })?;
        let Some(tables) = summary.pore_tables.clone() else {
            let why = summary
                .pores_note
                .clone()
                .unwrap_or_else(|| "the pore measures were not asked for".into());
            return Err(crate::errors::ImpossibleError::new_err(format!(
                "pores: {why}"
            )));
        };
        let json = serde_json::to_string(&summary).map_err(|e| config_error(e.to_string()))?;
        Ok((
            json,
            columns_dict(py, tables.pore_columns())?,
            columns_dict(py, tables.throat_columns())?,
        ))
    }

    /// The drainage with the analysis settings (`measures` given by the
    /// caller): the measures (JSON text) and, as dicts of numpy arrays, the
    /// curve, its rows with relative permeabilities, the pendular bridges
    /// and the pores' columns; raises `ImpossibleError` with the reason when
    /// the bed has no drainage.
    #[pyo3(signature = (settings_json, progress=None))]
    #[allow(clippy::type_complexity)]
    fn drainage<'py>(
        &self,
        py: Python<'py>,
        settings_json: &str,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<(
        String,
        Bound<'py, PyDict>,
        Bound<'py, PyDict>,
        Bound<'py, PyDict>,
        Bound<'py, PyDict>,
    )> {
        let settings = self.settings(settings_json)?;
        let bed = self.bed();
        let (_, summary) = detached::run(py, progress, |_| {
            packbed::analyze_bed(bed, &settings).map_err(to_py)
        })?;
        let (Some(d), Some(tables)) = (summary.liquid.clone(), summary.pore_tables.clone()) else {
            let why = summary
                .drainage_note
                .clone()
                .or_else(|| summary.pores_note.clone())
                .unwrap_or_else(|| "the drainage was not asked for".into());
            return Err(crate::errors::ImpossibleError::new_err(format!(
                "drainage: {why}"
            )));
        };
        let json = serde_json::to_string(&summary).map_err(|e| config_error(e.to_string()))?;
        Ok((
            json,
            columns_dict(py, d.curve_columns())?,
            columns_dict(py, d.relative_columns())?,
            columns_dict(py, d.bridge_columns())?,
            columns_dict(py, tables.pore_columns())?,
        ))
    }

    /// The drying with the analysis settings (`measures` given by the
    /// caller): the measures (JSON text), the columns of `bridges.csv` and
    /// `agglomerates.csv` as dicts of numpy arrays, and each particle's
    /// agglomerate (0: none); raises `ImpossibleError` with the reason when
    /// the bed has no drying.
    #[pyo3(signature = (settings_json, progress=None))]
    #[allow(clippy::type_complexity)]
    fn agglomeration<'py>(
        &self,
        py: Python<'py>,
        settings_json: &str,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<(
        String,
        Bound<'py, PyDict>,
        Bound<'py, PyDict>,
        Bound<'py, PyArray1<u32>>,
    )> {
        let settings = self.settings(settings_json)?;
        let bed = self.bed();
        let (_, summary) = detached::run(py, progress, |_| {
            packbed::analyze_bed(bed, &settings).map_err(to_py)
        })?;
        let Some(d) = summary.dried.clone() else {
            let why = summary
                .agglomeration_note
                .clone()
                .or_else(|| summary.pores_note.clone())
                .unwrap_or_else(|| "the agglomeration was not asked for".into());
            return Err(crate::errors::ImpossibleError::new_err(format!(
                "agglomeration: {why}"
            )));
        };
        let json = serde_json::to_string(&summary).map_err(|e| config_error(e.to_string()))?;
        Ok((
            json,
            columns_dict(py, d.bridge_columns())?,
            columns_dict(py, d.agglomerate_columns())?,
            PyArray1::from_vec(py, d.agglomerate_of.clone()),
        ))
    }

    /// Particle–particle contacts with the analysis settings: arrays i, j, gap.
    #[pyo3(signature = (settings_json))]
    #[allow(clippy::type_complexity)]
    fn contacts<'py>(
        &self,
        py: Python<'py>,
        settings_json: &str,
    ) -> PyResult<(
        Bound<'py, PyArray1<u32>>,
        Bound<'py, PyArray1<u32>>,
        Bound<'py, PyArray1<f64>>,
    )> {
        let settings = self.settings(settings_json)?;
        let bed = self.bed();
        let tol = settings.contact_tol;
        settings.check().map_err(to_py)?;
        let contacts = py.detach(|| match bed {
            AnyBed::D2(b) => packbed::find_contacts(b, tol),
            AnyBed::D3(b) => packbed::find_contacts(b, tol),
        });
        let i: Vec<u32> = contacts.pairs.iter().map(|c| c.i).collect();
        let j: Vec<u32> = contacts.pairs.iter().map(|c| c.j).collect();
        let gap: Vec<f64> = contacts.pairs.iter().map(|c| c.gap).collect();
        Ok((
            PyArray1::from_vec(py, i),
            PyArray1::from_vec(py, j),
            PyArray1::from_vec(py, gap),
        ))
    }

    /// Writes the bed's files into `out`: a built bed those of `packbed run`,
    /// a read bed those of `packbed analyze` (with `settings_json`). Returns
    /// the paths written.
    #[pyo3(signature = (out, settings_json, pictures=true))]
    fn write(
        &self,
        py: Python<'_>,
        out: PathBuf,
        settings_json: &str,
        pictures: bool,
    ) -> PyResult<Vec<PathBuf>> {
        let extras = RunExtras {
            pictures,
            exports: Vec::new(),
        };
        packbed::check_out_dir(&out).map_err(|e| to_py(e.within("out")))?;
        match &self.origin {
            Origin::Built(f) => {
                if settings_json != "{}" {
                    return Err(config_error(
                        "write: a built bed writes its run's files; analysis settings belong to its config",
                    ));
                }
                py.detach(|| f.write_with(&out, &extras).map(|w| w.files))
                    .map_err(to_py)
            }
            Origin::Read {
                bed,
                report,
                source,
            } => {
                let settings = self.settings(settings_json)?;
                let analyzed = py
                    .detach(|| {
                        packbed::analyze_read_bed(source, bed.clone(), report, &settings, 0.0)
                    })
                    .map_err(to_py)?;
                py.detach(|| analyzed.write_with(&out, &extras).map(|w| w.files))
                    .map_err(to_py)
            }
        }
    }

    /// Loads the bed and breaks bonds (`options_json`: the `[fragmentation]`
    /// table as JSON); returns the summary (JSON text) and, with `out`, writes
    /// the files of `packbed fragment` there.
    #[pyo3(signature = (options_json, contact_tol, out=None, pictures=true, progress=None))]
    fn fragment(
        &self,
        py: Python<'_>,
        options_json: &str,
        contact_tol: f64,
        out: Option<PathBuf>,
        pictures: bool,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<String> {
        let value: toml::Value =
            serde_json::from_str(options_json).map_err(|e| config_error(e.to_string()))?;
        let options: packbed::FragmentationConfig =
            value.try_into().map_err(|e: toml::de::Error| {
                config_error(format!("fragmentation: {}", e.message().trim()))
            })?;
        if let Some(dir) = &out {
            packbed::check_out_dir(dir).map_err(|e| to_py(e.within("out")))?;
        }
        let (source, report) = self.source();
        let bed = self.bed();
        let fragmented = detached::run(py, progress, |_| {
            packbed::fragment_read_bed(source, bed.clone(), &report, &options, contact_tol, 0.0)
                .map_err(to_py)
        })?;
        if let Some(dir) = &out {
            py.detach(|| fragmented.write(dir, pictures).map(|w| w.files))
                .map_err(to_py)?;
        }
        fragmented.summary.to_json().map_err(to_py)
    }
}

impl Bed {
    /// Analysis settings: a built bed's config's table, overridden by the
    /// keys of `settings_json`; a read bed's defaults, likewise.
    fn settings(&self, settings_json: &str) -> PyResult<AnalysisConfig> {
        let base = match &self.origin {
            Origin::Built(f) => f.summary.config.analysis.clone(),
            Origin::Read { .. } => AnalysisConfig::default(),
        };
        let mut table = toml::Value::try_from(&base).map_err(|e| config_error(e.to_string()))?;
        let given: toml::Value =
            serde_json::from_str(settings_json).map_err(|e| config_error(e.to_string()))?;
        if let (Some(t), Some(g)) = (table.as_table_mut(), given.as_table()) {
            for (k, v) in g {
                t.insert(k.clone(), v.clone());
            }
        }
        let settings: AnalysisConfig = table.try_into().map_err(|e: toml::de::Error| {
            config_error(format!("analysis: {}", e.message().trim()))
        })?;
        settings.check().map_err(to_py)?;
        Ok(settings)
    }
}

/// Builds the bed of a resolved config (canonical JSON) and analyses it.
#[pyfunction]
#[pyo3(signature = (config_json, progress=None))]
pub fn deposit(
    py: Python<'_>,
    config_json: &str,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<Bed> {
    let config = load(config_json)?;
    let finished = detached::run(py, progress, |shared: &Shared| {
        shared
            .total
            .store(config.estimated_particles(), Ordering::Relaxed);
        packbed::run_bed_or_stop(&config, &mut |n| {
            shared.done.store(n, Ordering::Relaxed);
            match shared.stopped() {
                true => ControlFlow::Break(()),
                false => ControlFlow::Continue(()),
            }
        })
        .map_err(to_py)
    })?;
    Ok(Bed {
        origin: Origin::Built(Box::new(finished)),
    })
}

/// Reads a bed file (every format `packbed analyze` reads); `size` and
/// `periodic` give the box of a file without one.
#[pyfunction]
#[pyo3(signature = (path, size=None, periodic=None))]
pub fn read(
    py: Python<'_>,
    path: PathBuf,
    size: Option<Vec<f64>>,
    periodic: Option<bool>,
) -> PyResult<Bed> {
    let hint = match (size, periodic) {
        (None, None) => None,
        (None, Some(_)) => return Err(config_error("periodic: give the box too")),
        (Some(size), p) => Some(BoxHint {
            size,
            periodic: p.unwrap_or(false),
        }),
    };
    if let Some(h) = &hint {
        packbed::check_box_hint(h).map_err(|e| to_py(e.within("box")))?;
    }
    let (bed, report) = py
        .detach(|| packbed::read_bed_report(Path::new(&path), hint.as_ref()))
        .map_err(to_py)?;
    Ok(Bed {
        origin: Origin::Read {
            bed,
            report,
            source: path.display().to_string(),
        },
    })
}
