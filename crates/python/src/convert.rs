//! Small conversions between Python values and Irradia's: JSON documents to Python
//! objects (the ray tree, the light and material records), three-vectors and colours
//! from any sequence of three numbers, with the field named in the error.

use crate::errors;
use irradia_core::{Rgb, Vec3};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use serde_json::Value;

/// A JSON value as the Python object `json.loads` would give.
pub fn json_to_py(py: Python<'_>, v: &Value) -> PyResult<PyObject> {
    Ok(match v {
        Value::Null => py.None(),
        Value::Bool(b) => b.into_pyobject(py)?.to_owned().into_any().unbind(),
        Value::Number(n) => match (n.as_i64(), n.as_u64()) {
            (Some(i), _) => i.into_pyobject(py)?.into_any().unbind(),
            (None, Some(u)) => u.into_pyobject(py)?.into_any().unbind(),
            _ => n
                .as_f64()
                .unwrap_or(f64::NAN)
                .into_pyobject(py)?
                .into_any()
                .unbind(),
        },
        Value::String(s) => s.into_pyobject(py)?.into_any().unbind(),
        Value::Array(a) => {
            let list = PyList::empty(py);
            for x in a {
                list.append(json_to_py(py, x)?)?;
            }
            list.into_any().unbind()
        }
        Value::Object(m) => {
            let d = PyDict::new(py);
            for (k, x) in m {
                d.set_item(k, json_to_py(py, x)?)?;
            }
            d.into_any().unbind()
        }
    })
}

/// Three finite numbers from a sequence (a list, tuple or numpy array); `field` names
/// the argument in the error.
pub fn vec3(obj: &Bound<'_, PyAny>, field: &str) -> PyResult<Vec3> {
    let v: Vec<f32> = obj
        .extract()
        .map_err(|_| errors::input(format!("{field}: expected three numbers")))?;
    match v.as_slice() {
        [x, y, z] if x.is_finite() && y.is_finite() && z.is_finite() => Ok(Vec3::new(*x, *y, *z)),
        [_, _, _] => Err(errors::input(format!(
            "{field}: must be finite numbers (got {v:?})"
        ))),
        _ => Err(errors::input(format!(
            "{field}: expected three numbers, got {}",
            v.len()
        ))),
    }
}

/// An RGB colour: three numbers, or one for grey; negative values are refused.
pub fn rgb(obj: &Bound<'_, PyAny>, field: &str) -> PyResult<Rgb> {
    if let Ok(x) = obj.extract::<f32>() {
        return rgb_of([x, x, x], field);
    }
    let v = vec3(obj, field)?;
    rgb_of([v.x, v.y, v.z], field)
}

fn rgb_of(c: [f32; 3], field: &str) -> PyResult<Rgb> {
    if c.iter().any(|x| !(x.is_finite() && *x >= 0.0)) {
        return Err(errors::input(format!(
            "{field}: a colour must be finite and not negative (got {c:?})"
        )));
    }
    Ok(Rgb::from_array(c))
}

/// A finite number, not negative.
pub fn non_negative(obj: &Bound<'_, PyAny>, field: &str) -> PyResult<f32> {
    let x: f32 = obj
        .extract()
        .map_err(|_| errors::input(format!("{field}: expected a number")))?;
    if !(x.is_finite() && x >= 0.0) {
        return Err(errors::input(format!(
            "{field}: must be a finite number, not negative (got {x})"
        )));
    }
    Ok(x)
}

/// The values of an array in row-major order: a C-contiguous array is read in place,
/// any other copied once (through a dynamic-rank iterator, which is slow per element).
/// (`as_slice` alone is not enough: it also lends a Fortran-ordered array's memory,
/// whose order is column-major.)
pub fn values<'a, T: numpy::Element + Copy>(
    a: &'a numpy::PyReadonlyArrayDyn<'_, T>,
) -> std::borrow::Cow<'a, [T]> {
    use numpy::PyUntypedArrayMethods;
    match a.as_slice() {
        Ok(s) if a.is_c_contiguous() => std::borrow::Cow::Borrowed(s),
        _ => std::borrow::Cow::Owned(a.as_array().as_standard_layout().iter().copied().collect()),
    }
}
