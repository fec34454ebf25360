//! Thin PyO3 binding: JSON model and options in, NumPy arrays and a JSON summary out;
//! the engine's defaults and resolved values out as JSON, its errors in parts.
use numpy::{PyArray1, PyArray2};
use pyo3::exceptions::{PyKeyboardInterrupt, PyValueError};
use pyo3::prelude::*;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use jointgap_core::simulate::any::{AnyModel, AnyPrepared};

pyo3::create_exception!(
    _jointgap,
    EngineError,
    PyValueError,
    "An error of the engine; its attributes `category`, `kind`, `element`, `key` and \
     `problem` hold the parts of the message."
);

/// An engine error as an [`EngineError`] whose attributes are its parts
/// ([`jointgap_core::Error::parts`]), so that Python reads them instead of the message.
fn to_py_err(e: jointgap_core::Error) -> PyErr {
    let parts = e.parts();
    let error = EngineError::new_err(e.to_string());
    Python::with_gil(|py| -> PyResult<()> {
        let value = error.value(py);
        value.setattr("category", parts.category)?;
        value.setattr("kind", parts.kind)?;
        value.setattr("element", parts.element)?;
        value.setattr("key", parts.key)?;
        value.setattr("problem", parts.problem)?;
        Ok(())
    })
    .map_or_else(|failed| failed, |()| error)
}

/// The engine's defaults ([`jointgap_core::simulate::all_defaults::defaults`]) as JSON: `gravity`,
/// `normal_law` (`exponent`, `clip`) and `options` (every run option but `t_end`).
#[pyfunction]
fn defaults() -> PyResult<String> {
    serde_json::to_string(&jointgap_core::simulate::all_defaults::defaults())
        .map_err(|e| PyValueError::new_err(e.to_string()))
}

fn parse(model_json: &str, options_json: &str) -> PyResult<(AnyModel, jointgap_core::SimOptions)> {
    let model = AnyModel::from_json(model_json).map_err(to_py_err)?;
    let options: jointgap_core::SimOptions =
        serde_json::from_str(options_json).map_err(|e| PyValueError::new_err(format!("options: {e}")))?;
    Ok((model, options))
}

/// The models this process prepared last (compiled and assembled), keyed by their JSON
/// text, the most recent last: loading a model checks it, and its run, the estimate of
/// its output size and the check itself then share one compilation. Preparing is a pure
/// function of the text, so a model found here is the one a new compilation would give.
static PREPARED: Mutex<Vec<(String, Arc<AnyPrepared>)>> = Mutex::new(Vec::new());

/// How many prepared models [`PREPARED`] keeps: a few, for the threads of a study or an
/// identification that run different models at once; a batch's estimate of its output
/// size ([`channel_counts`]) keeps all of its models, however many, for its run.
const PREPARED_KEPT: usize = 8;

/// The kept prepared models; a panic while one was held leaves the list valid.
fn kept() -> MutexGuard<'static, Vec<(String, Arc<AnyPrepared>)>> {
    PREPARED.lock().unwrap_or_else(PoisonError::into_inner)
}

/// The prepared model of `model_json` (parsed as `model`), kept or prepared now.
fn prepared(model_json: &str, model: &AnyModel) -> Result<Arc<AnyPrepared>, jointgap_core::Error> {
    prepared_keeping(model_json, model, PREPARED_KEPT)
}

/// [`prepared`], the list then keeping the last `keep` models.
fn prepared_keeping(
    model_json: &str,
    model: &AnyModel,
    keep: usize,
) -> Result<Arc<AnyPrepared>, jointgap_core::Error> {
    if let Some(found) = kept_prepared(model_json) {
        return Ok(found);
    }
    let prepared = Arc::new(AnyPrepared::new(model)?);
    let mut kept = kept();
    kept.push((model_json.to_string(), Arc::clone(&prepared)));
    let over = kept.len().saturating_sub(keep);
    kept.drain(..over);
    Ok(prepared)
}

/// The prepared model of a batch's `model_json`: the kept one (its output size was
/// estimated), else prepared now for its run alone (a batch without a rate: its models
/// are not kept, they would push out those of the runs and checks the list is for).
fn batch_prepared(model_json: &str, model: &AnyModel) -> Result<Arc<AnyPrepared>, jointgap_core::Error> {
    match kept_prepared(model_json) {
        Some(found) => Ok(found),
        None => Ok(Arc::new(AnyPrepared::new(model)?)),
    }
}

/// The kept prepared model of `model_json`, if any.
fn kept_prepared(model_json: &str) -> Option<Arc<AnyPrepared>> {
    kept().iter().rev().find(|(text, _)| text == model_json).map(|(_, p)| Arc::clone(p))
}

/// How many models this process has compiled ([`jointgap_core::system::compilations`]),
/// kept ones counted once: a test reads it to see that loading a model and running it,
/// alone or in a batch, compiles the model once.
#[pyfunction]
fn compilations() -> usize {
    jointgap_core::system::compilations()
}

/// Checks a model (JSON, SI units) as far as a run goes before its first step (assembled,
/// every channel evaluated at t = 0); returns its warnings and raises EngineError naming
/// the offending element, as a run would. The prepared model is kept for its run.
#[pyfunction]
fn check_model(model_json: &str) -> PyResult<Vec<String>> {
    let model = AnyModel::from_json(model_json).map_err(to_py_err)?;
    let prepared = prepared(model_json, &model).map_err(to_py_err)?;
    prepared.check().map_err(to_py_err)
}

/// Each clearance joint as the engine resolves it ([`jointgap_core::system::resolved`]: radii,
/// clearance, stiffness computed from the materials, exponent, `d_max`, the laws in force)
/// as a JSON list, without running the model.
#[pyfunction]
fn clearance_data(model_json: &str) -> PyResult<String> {
    let model = AnyModel::from_json(model_json).map_err(to_py_err)?;
    let data = jointgap_core::simulate::any::clearances(&model).map_err(to_py_err)?;
    serde_json::to_string(&data).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// The channel names a run records, in result order, without running: with options, those
/// a run with them records (of the model prepared and kept for its run, so it must
/// assemble); without, every channel of the model (in model order).
#[pyfunction]
#[pyo3(signature = (model_json, options_json=None))]
fn channel_names(model_json: &str, options_json: Option<&str>) -> PyResult<Vec<String>> {
    let Some(options_json) = options_json else {
        let model = AnyModel::from_json(model_json).map_err(to_py_err)?;
        return jointgap_core::simulate::any::channel_names(&model).map_err(to_py_err);
    };
    let (model, options) = parse(model_json, options_json)?;
    let prepared = prepared(model_json, &model).map_err(to_py_err)?;
    prepared.recorded_channels(&options).map_err(to_py_err)
}

/// How many channels a run of each model with the options records ([`channel_names`]),
/// `None` for a model the engine refuses (its run says why): a batch's estimate of its
/// output size. Every model is prepared and kept for the batch's run, however many.
#[pyfunction]
fn channel_counts(
    py: Python<'_>,
    models_json: Vec<String>,
    options_json: &str,
) -> PyResult<Vec<Option<usize>>> {
    let options: jointgap_core::SimOptions =
        serde_json::from_str(options_json).map_err(|e| PyValueError::new_err(format!("options: {e}")))?;
    let keep = PREPARED_KEPT.max(models_json.len());
    let count = |model_json: &String| {
        let model = AnyModel::from_json(model_json).ok()?;
        let prepared = prepared_keeping(model_json, &model, keep).ok()?;
        let names = prepared.recorded_channels(&options).ok()?;
        Some(names.len())
    };
    Ok(py.allow_threads(|| models_json.iter().map(count).collect()))
}

type Arrays<'py> = (Bound<'py, PyArray1<f64>>, Vec<String>, Bound<'py, PyArray2<f64>>, String);

/// A result as `(time, names, data[n_channels, n_samples], summary_json)`.
fn to_python<'py>(py: Python<'py>, result: jointgap_core::SimResult) -> PyResult<Arrays<'py>> {
    let summary = serde_json::json!({
        "stats": result.stats,
        "status": result.status,
        "warnings": result.warnings,
        "impacts": result.impacts,
        "clearances": result.clearances,
        "wear": result.wear,
        "samples": result.samples,
        "peaks": result.peaks,
    });
    let (time, data) = samples_to_python(py, &result.time, &result.data)?;
    Ok((time, result.names, data, summary.to_string()))
}

type Samples<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray2<f64>>);

/// `(time, data[n_channels, n_samples])` as NumPy arrays.
fn samples_to_python<'py>(py: Python<'py>, time: &[f64], data: &[Vec<f64>]) -> PyResult<Samples<'py>> {
    let flat: Vec<f64> = data.iter().flatten().copied().collect();
    let table = numpy::ndarray::Array2::from_shape_vec((data.len(), time.len()), flat)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok((PyArray1::from_slice(py, time), PyArray2::from_owned_array(py, table)))
}

/// Calls back into Python while a run goes (the GIL taken only for the call): the
/// progress callable, the sink of sample chunks, and a check for Ctrl-C, so that a long
/// run can be interrupted. Ctrl-C (a `KeyboardInterrupt`, from the check or raised in a
/// callable) ends the run with status interrupted and what it computed; any other
/// Python exception stops the run and is re-raised.
struct PyMonitor {
    progress: Option<PyObject>,
    sink: Option<PyObject>,
    chunk: Option<usize>,
    interval: f64,
    error: Option<PyErr>,
}

/// Ctrl-C interrupts the run; any other exception is kept in `first` (the first one
/// wins) to be raised again when the run has returned.
fn stop(py: Python<'_>, first: &mut Option<PyErr>, error: PyErr) -> jointgap_core::Stop {
    if error.is_instance_of::<PyKeyboardInterrupt>(py) {
        return jointgap_core::Stop::Interrupted;
    }
    let text = error.to_string();
    first.get_or_insert(error);
    jointgap_core::Stop::Error(text)
}

impl jointgap_core::Monitor for PyMonitor {
    fn progress_interval(&self) -> Option<f64> {
        Some(self.interval)
    }

    fn progress(&mut self, p: &jointgap_core::Progress) -> Result<(), jointgap_core::Stop> {
        Python::with_gil(|py| {
            let outcome = py.check_signals().and_then(|()| match &self.progress {
                Some(callback) => callback.call1(py, (p.time, p.steps, p.impacts)).map(|_| ()),
                None => Ok(()),
            });
            outcome.map_err(|e| stop(py, &mut self.error, e))
        })
    }

    fn chunk_len(&self) -> Option<usize> {
        self.sink.as_ref().and(self.chunk)
    }

    fn samples(
        &mut self,
        names: &[String],
        time: &[f64],
        data: &[Vec<f64>],
    ) -> Result<(), jointgap_core::Stop> {
        let Some(sink) = &self.sink else { return Ok(()) };
        Python::with_gil(|py| {
            let outcome = samples_to_python(py, time, data)
                .and_then(|(t, table)| sink.call1(py, (names.to_vec(), t, table)).map(|_| ()));
            outcome.map_err(|e| stop(py, &mut self.error, e))
        })
    }
}

/// Runs a simulation with the GIL released. Returns
/// `(time, names, data[n_channels, n_samples], summary_json)`. `progress(t, steps,
/// impacts)` is called about every `interval` seconds of wall time (default 0.2; 0 calls
/// it at every check, every 16 accepted steps), when Ctrl-C is checked too; with `sink`,
/// the samples are handed to `sink(names, time, data)` in chunks of `chunk` samples as
/// the run goes, and the returned arrays hold none of them. Ctrl-C returns what was
/// computed with status interrupted.
#[pyfunction]
// `interval`: wall-clock seconds between progress reports (and Ctrl-C checks). Its default
// is a literal, as in `simulate_batch`, so that the signature Python sees shows it (a
// named constant reads `...`) and `mypy.stubtest` checks it against the stub.
#[pyo3(signature = (model_json, options_json, progress=None, sink=None, chunk=8192, interval=0.2))]
fn simulate<'py>(
    py: Python<'py>,
    model_json: &str,
    options_json: &str,
    progress: Option<PyObject>,
    sink: Option<PyObject>,
    chunk: usize,
    interval: f64,
) -> PyResult<Arrays<'py>> {
    let (model, options) = parse(model_json, options_json)?;
    if chunk == 0 {
        return Err(PyValueError::new_err("chunk = 0: must be at least 1 sample"));
    }
    check_interval(interval)?;
    options.check().map_err(to_py_err)?;
    let mut monitor = PyMonitor { progress, sink, chunk: Some(chunk), interval, error: None };
    let result = py
        .allow_threads(|| {
            let prepared = prepared(model_json, &model)?;
            prepared.run(&options, &mut monitor, std::time::Instant::now())
        })
        .map_err(to_py_err)?;
    if let Some(error) = monitor.error {
        return Err(error);
    }
    to_python(py, result)
}

/// One slot of a batch: `(arrays, None)`, `(None, error)` for a model that could not
/// run (an [`EngineError`]), `(None, None)` for one that Ctrl-C kept from starting.
type Slot<'py> = (Option<Arrays<'py>>, Option<PyObject>);

/// Runs many models with the same options on `threads` threads (all cores by default),
/// the GIL released while they run. Returns `(slots, interrupted)`: in order, each
/// model's [`Slot`], and whether Ctrl-C (or a KeyboardInterrupt raised by `progress`)
/// stopped the batch. The calling thread waits, checking Ctrl-C and calling
/// `progress(running, ended)` (cases running, cases ended) every `interval` seconds of
/// wall time; on Ctrl-C the runs going end as interrupted with what they computed and
/// the cases not started are not run. Any other exception of `progress` stops the batch
/// in the same way and is raised again when the runs have returned.
/// A model this process holds prepared (its output size was just estimated) runs without
/// being compiled again; the others are prepared once, in the batch's threads.
#[pyfunction]
#[pyo3(signature = (models_json, options_json, threads=None, progress=None, interval=0.2))]
fn simulate_batch<'py>(
    py: Python<'py>,
    models_json: Vec<String>,
    options_json: &str,
    threads: Option<usize>,
    progress: Option<PyObject>,
    interval: f64,
) -> PyResult<(Vec<Slot<'py>>, bool)> {
    let options: jointgap_core::SimOptions =
        serde_json::from_str(options_json).map_err(|e| PyValueError::new_err(format!("options: {e}")))?;
    check_interval(interval)?;
    let parsed: Vec<Result<AnyModel, jointgap_core::Error>> =
        models_json.iter().map(|m| AnyModel::from_json(m)).collect();
    let valid: Vec<(&str, &AnyModel)> = models_json
        .iter()
        .zip(&parsed)
        .filter_map(|(json, m)| Some((json.as_str(), m.as_ref().ok()?)))
        .collect();
    let control = jointgap_core::BatchControl::default();
    let (results, error) = py.allow_threads(|| {
        std::thread::scope(|scope| {
            let (done, wait) = std::sync::mpsc::channel();
            let (valid, options, control) = (&valid, &options, &control);
            let runs = scope.spawn(move || {
                let prepare = |(json, model): &(&str, &AnyModel)| batch_prepared(json, model);
                let results =
                    jointgap_core::simulate::simulate_batch_of(valid, prepare, options, threads, control);
                let _ = done.send(());
                results
            });
            let error = watch_batch(control, &wait, progress.as_ref(), interval);
            // A panic in the engine is a bug, reported as such by PyO3 in this thread.
            let results = runs.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            (results, error)
        })
    });
    // The batch's models, kept for its run, make way again.
    {
        let mut kept = kept();
        let over = kept.len().saturating_sub(PREPARED_KEPT);
        kept.drain(..over);
    }
    if let Some(error) = error {
        return Err(error);
    }
    let mut results = results.into_iter();
    let slots = parsed
        .into_iter()
        .map(|m| match m {
            Err(e) => Ok((None, Some(to_py_err(e).into_value(py).into_any()))),
            Ok(_) => match results.next().expect("one result per valid model") {
                Some(Ok(result)) => Ok((Some(to_python(py, result)?), None)),
                Some(Err(e)) => Ok((None, Some(to_py_err(e).into_value(py).into_any()))),
                None => Ok((None, None)),
            },
        })
        .collect::<PyResult<Vec<_>>>()?;
    Ok((slots, control.stopped()))
}

/// Waits for a batch to end (`ended` receives once the runs have returned), taking the
/// GIL every `interval` seconds, and once at the end, to check Ctrl-C and call
/// `progress(running, ended)`. Ctrl-C, or an exception of `progress`, stops the batch (`control`); the exception is
/// returned unless it is a KeyboardInterrupt.
fn watch_batch(
    control: &jointgap_core::BatchControl,
    ended: &std::sync::mpsc::Receiver<()>,
    progress: Option<&PyObject>,
    interval: f64,
) -> Option<PyErr> {
    // At least a millisecond between checks: interval 0 must not spin a core the runs need.
    let period = std::time::Duration::from_secs_f64(interval.max(1e-3));
    let mut error = None;
    loop {
        // Once more after the end: a Ctrl-C of the last moment marks the batch, not the
        // caller's next line.
        let over = !matches!(ended.recv_timeout(period), Err(std::sync::mpsc::RecvTimeoutError::Timeout));
        if !control.stopped() {
            let outcome = Python::with_gil(|py| {
                let checked = py.check_signals().and_then(|()| match progress {
                    Some(callback) => callback.call1(py, (control.running(), control.ended())).map(|_| ()),
                    None => Ok(()),
                });
                checked.map_err(|e| (!e.is_instance_of::<PyKeyboardInterrupt>(py)).then_some(e))
            });
            if let Err(raised) = outcome {
                control.stop();
                error = raised;
            }
        }
        if over {
            return error;
        }
    }
}

/// `interval` of `simulate` and `simulate_batch`: finite seconds, at least 0.
fn check_interval(interval: f64) -> PyResult<()> {
    if interval >= 0.0 && interval.is_finite() {
        return Ok(());
    }
    Err(PyValueError::new_err(format!("interval = {interval}: must be a finite number of seconds >= 0")))
}

/// The compiled core of jointgap.
#[pymodule]
fn _jointgap(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("EngineError", m.py().get_type::<EngineError>())?;
    m.add_function(wrap_pyfunction!(defaults, m)?)?;
    m.add_function(wrap_pyfunction!(compilations, m)?)?;
    m.add_function(wrap_pyfunction!(check_model, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(clearance_data, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_batch, m)?)?;
    m.add_function(wrap_pyfunction!(channel_names, m)?)?;
    m.add_function(wrap_pyfunction!(channel_counts, m)?)?;
    Ok(())
}
