use std::path::Path;

use crate::DataError;

/// A metadata value.
#[derive(Debug, Clone, PartialEq)]
pub enum AttrValue {
    /// A real number.
    Float(f64),
    /// An integer.
    Int(i64),
    /// Text.
    Text(String),
}

impl AttrValue {
    /// As JSON.
    pub fn to_json(&self) -> serde_json::Value {
        match self {
            AttrValue::Float(v) => serde_json::json!(v),
            AttrValue::Int(v) => serde_json::json!(v),
            AttrValue::Text(v) => serde_json::json!(v),
        }
    }
}

/// Named `f64` arrays (1D, or C-order with a shape) with named metadata: what the CLI writes and
/// the fixtures hold.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Record {
    /// `(name, values)`, in order.
    pub arrays: Vec<(String, Vec<f64>)>,
    /// `(name, value)`, in order.
    pub attributes: Vec<(String, AttrValue)>,
    /// `(name, shape)` of the arrays that are not 1D (C order, slowest index first).
    pub shapes: Vec<(String, Vec<usize>)>,
}

impl Record {
    /// Adds an array.
    pub fn array(mut self, name: &str, values: Vec<f64>) -> Self {
        self.arrays.push((name.to_string(), values));
        self
    }

    /// Adds an array of the given shape (C order); the product of `shape` must be its length.
    pub fn shaped(mut self, name: &str, values: Vec<f64>, shape: &[usize]) -> Self {
        self.shapes.push((name.to_string(), shape.to_vec()));
        self.arrays.push((name.to_string(), values));
        self
    }

    /// The shape of array `name` (`[len]` when 1D).
    pub fn shape_of(&self, name: &str) -> Option<Vec<usize>> {
        let len = self.get(name)?.len();
        Some(
            self.shapes
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, s)| s.clone())
                .unwrap_or_else(|| vec![len]),
        )
    }

    /// Adds a metadata entry.
    pub fn attr(mut self, name: &str, value: AttrValue) -> Self {
        self.attributes.push((name.to_string(), value));
        self
    }

    /// The array called `name`.
    pub fn get(&self, name: &str) -> Option<&[f64]> {
        self.arrays
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }

    /// The metadata entry called `name`.
    pub fn get_attr(&self, name: &str) -> Option<&AttrValue> {
        self.attributes
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v)
    }

    /// The metadata entry called `name` when it is a real number.
    pub fn float_attr(&self, name: &str) -> Option<f64> {
        match self.get_attr(name) {
            Some(AttrValue::Float(v)) => Some(*v),
            _ => None,
        }
    }

    /// Metadata as one JSON object.
    pub fn metadata_json(&self) -> serde_json::Value {
        serde_json::Value::Object(
            self.attributes
                .iter()
                .map(|(k, v)| (k.clone(), v.to_json()))
                .collect(),
        )
    }

    pub(crate) fn validate(&self, path: &Path) -> Result<(), DataError> {
        let bad = |message: String| DataError::InvalidContent {
            path: path.to_path_buf(),
            message,
        };
        for (i, (name, _)) in self.arrays.iter().enumerate() {
            if name.is_empty() || name == "metadata" || name.contains('/') {
                return Err(bad(format!("array name '{name}' is reserved or invalid")));
            }
            if self.arrays[..i].iter().any(|(n, _)| n == name) {
                return Err(bad(format!("array '{name}' appears twice")));
            }
        }
        for (name, shape) in &self.shapes {
            let len = self.get(name).map(|v| v.len());
            if len != Some(shape.iter().product()) {
                return Err(bad(format!(
                    "array '{name}': shape {shape:?} does not match its length {len:?}"
                )));
            }
        }
        Ok(())
    }
}
