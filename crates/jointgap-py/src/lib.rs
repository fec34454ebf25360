//! Thin PyO3 binding: JSON model and options in, NumPy arrays and a JSON summary out.
use numpy::{PyArray1, PyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

fn to_py_err(e: jointgap_core::Error) -> PyErr {
    PyValueError::new_err(e.to_string())
}

fn parse(
    model_json: &str,
    options_json: &str,
) -> PyResult<(jointgap_core::Model, jointgap_core::SimOptions)> {
    let model = jointgap_core::Model::from_json(model_json).map_err(to_py_err)?;
    let options: jointgap_core::SimOptions =
        serde_json::from_str(options_json).map_err(|e| PyValueError::new_err(format!("options: {e}")))?;
    Ok((model, options))
}

/// Checks a model (JSON, SI units) and assembles it at t = 0; returns its warnings and
/// raises ValueError naming the offending element.
#[pyfunction]
fn check_model(model_json: &str) -> PyResult<Vec<String>> {
    let model = jointgap_core::Model::from_json(model_json).map_err(to_py_err)?;
    let prepared = jointgap_core::solve::prepare(&model).map_err(to_py_err)?;
    Ok(prepared.system.warnings)
}

/// Each clearance joint's resolved contact data (radii, clearance, stiffness computed
/// from the materials, exponent) as a JSON list, without running the model.
#[pyfunction]
fn clearance_data(model_json: &str) -> PyResult<String> {
    let model = jointgap_core::Model::from_json(model_json).map_err(to_py_err)?;
    let system = jointgap_core::System::new(&model).map_err(to_py_err)?;
    let data: Vec<_> = system.clearances.iter().map(|c| c.data()).collect();
    serde_json::to_string(&data).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// Runs a simulation with the GIL released. Returns
/// `(time, names, data[n_channels, n_samples], summary_json)`.
#[pyfunction]
#[allow(clippy::type_complexity)]
fn simulate<'py>(
    py: Python<'py>,
    model_json: &str,
    options_json: &str,
) -> PyResult<(Bound<'py, PyArray1<f64>>, Vec<String>, Bound<'py, PyArray2<f64>>, String)> {
    let (model, options) = parse(model_json, options_json)?;
    let result = py.allow_threads(|| jointgap_core::simulate(&model, &options)).map_err(to_py_err)?;
    let summary = serde_json::json!({
        "stats": result.stats,
        "status": result.status,
        "warnings": result.warnings,
        "impacts": result.impacts,
        "clearances": result.clearances,
    });
    let n = result.time.len();
    let flat: Vec<f64> = result.data.iter().flatten().copied().collect();
    let data = numpy::ndarray::Array2::from_shape_vec((result.names.len(), n), flat)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok((
        PyArray1::from_vec(py, result.time),
        result.names,
        PyArray2::from_owned_array(py, data),
        summary.to_string(),
    ))
}

/// The compiled core of jointgap.
#[pymodule]
fn _jointgap(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(check_model, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(clearance_data, m)?)?;
    Ok(())
}
