//! Python values as the JSON values configs and the knob table read: None, bools, numbers,
//! strings, lists and tuples, dicts with string keys (numpy scalars too, by `__index__` or
//! `__float__`), so that a keyword option and a config field go through the same reader.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use serde_json::{Map, Number, Value};

/// `what` names the value in the error (`option "spp"`).
pub fn to_json(v: &Bound<'_, PyAny>, what: &str) -> Result<Value, String> {
    if v.is_none() {
        return Ok(Value::Null);
    }
    if let Ok(b) = v.cast::<PyBool>() {
        return Ok(Value::Bool(b.is_true()));
    }
    if v.is_instance_of::<PyInt>()
        || (!v.is_instance_of::<PyFloat>() && v.hasattr("__index__").unwrap_or(false))
    {
        if let Ok(i) = v.extract::<i64>() {
            return Ok(Value::Number(i.into()));
        }
        if let Ok(u) = v.extract::<u64>() {
            return Ok(Value::Number(u.into()));
        }
        return Err(format!("{what}: the integer {v} is out of range"));
    }
    if v.is_instance_of::<PyFloat>() || v.hasattr("__float__").unwrap_or(false) {
        let f: f64 = v.extract().map_err(|e| format!("{what}: {e}"))?;
        return Number::from_f64(f)
            .map(Value::Number)
            .ok_or_else(|| format!("{what}: expected a finite number, found {f}"));
    }
    if let Ok(s) = v.cast::<PyString>() {
        return Ok(Value::String(s.to_string()));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        return v
            .try_iter()
            .map_err(|e| e.to_string())?
            .map(|x| to_json(&x.map_err(|e| e.to_string())?, what))
            .collect();
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut map = Map::new();
        for (k, x) in d.iter() {
            let key: String = k.extract().map_err(|_| format!("{what}: a dict key is not a string: {k}"))?;
            let inner = format!("{what}.{key}");
            map.insert(key, to_json(&x, &inner)?);
        }
        return Ok(Value::Object(map));
    }
    let type_name = v.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "?".into());
    Err(format!("{what}: cannot take a value of type {type_name} (expected None, a bool, a number, a string, a list or a dict)"))
}
