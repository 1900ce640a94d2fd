//! Reading the JSON files of a run with errors that name the file, the place in it
//! (`angles[1].bip_error_mm.mean`) and what was expected there.

use std::path::Path;

use serde_json::Value;

use super::ReportError;

/// Reads and parses the JSON file `path`; `what` says what it should be (for the message when
/// it is missing or does not parse).
pub fn read_json_file(path: &Path, what: &str) -> Result<Value, ReportError> {
    let bytes = std::fs::read(path)
        .map_err(|e| ReportError::input(path, format!("could not read {what}: {e}")))?;
    serde_json::from_slice(&bytes).map_err(|e| {
        ReportError::input(
            path,
            format!(
                "line {} column {}: expected {what} (JSON): {e}",
                e.line(),
                e.column()
            ),
        )
    })
}

/// A value inside a JSON file, with the way to it.
#[derive(Clone, Debug)]
pub struct Node<'a> {
    file: &'a Path,
    at: String,
    value: &'a Value,
}

/// What kind of JSON value `v` is, for messages.
fn kind(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

impl<'a> Node<'a> {
    /// The whole document of `file`.
    pub fn root(file: &'a Path, value: &'a Value) -> Node<'a> {
        Node {
            file,
            at: String::new(),
            value,
        }
    }

    /// The JSON value itself.
    pub fn value(&self) -> &'a Value {
        self.value
    }

    /// Where this value is, e.g. `angles[0].scan_angle_deg` (`the top level` for the root).
    pub fn place(&self) -> &str {
        if self.at.is_empty() {
            "the top level"
        } else {
            &self.at
        }
    }

    /// An error at this value: `expected`, and what was found.
    pub fn error(&self, expected: &str) -> ReportError {
        ReportError::input(
            self.file,
            format!(
                "{}: expected {expected}, found {}",
                self.place(),
                kind(self.value)
            ),
        )
    }

    fn child(&self, key: &str, value: &'a Value) -> Node<'a> {
        let at = if self.at.is_empty() {
            key.to_owned()
        } else {
            format!("{}.{key}", self.at)
        };
        Node {
            file: self.file,
            at,
            value,
        }
    }

    /// The member `key` of this object; an error if this is not an object or `key` is absent.
    pub fn get(&self, key: &str) -> Result<Node<'a>, ReportError> {
        let Value::Object(map) = self.value else {
            return Err(self.error(&format!("an object with \"{key}\"")));
        };
        match map.get(key) {
            Some(v) => Ok(self.child(key, v)),
            None => Err(ReportError::input(
                self.file,
                format!("{}: expected a member \"{key}\", found none", self.place()),
            )),
        }
    }

    /// The member `key`, `None` if it is absent or null.
    pub fn opt(&self, key: &str) -> Option<Node<'a>> {
        match self.value.get(key) {
            None | Some(Value::Null) => None,
            Some(v) => Some(self.child(key, v)),
        }
    }

    /// Whether the member `key` exists (even as null).
    pub fn has(&self, key: &str) -> bool {
        self.value.get(key).is_some()
    }

    /// This value as a number.
    pub fn f64(&self) -> Result<f64, ReportError> {
        self.value.as_f64().ok_or_else(|| self.error("a number"))
    }

    /// This value as a number, `None` for null (a statistic of nothing).
    pub fn opt_f64(&self) -> Result<Option<f64>, ReportError> {
        match self.value {
            Value::Null => Ok(None),
            _ => self.f64().map(Some),
        }
    }

    /// This value as a non-negative integer.
    pub fn u64(&self) -> Result<u64, ReportError> {
        self.value
            .as_u64()
            .ok_or_else(|| self.error("a non-negative integer"))
    }

    /// This value as a boolean.
    pub fn bool(&self) -> Result<bool, ReportError> {
        self.value
            .as_bool()
            .ok_or_else(|| self.error("true or false"))
    }

    /// This value as a string.
    pub fn str(&self) -> Result<&'a str, ReportError> {
        self.value.as_str().ok_or_else(|| self.error("a string"))
    }

    /// The elements of this array.
    pub fn array(&self) -> Result<Vec<Node<'a>>, ReportError> {
        let Value::Array(items) = self.value else {
            return Err(self.error("an array"));
        };
        Ok(items
            .iter()
            .enumerate()
            .map(|(i, v)| Node {
                file: self.file,
                at: format!("{}[{i}]", self.at),
                value: v,
            })
            .collect())
    }

    /// The members of this object, in the file's order (serde_json keeps keys sorted).
    pub fn members(&self) -> Result<Vec<(&'a str, Node<'a>)>, ReportError> {
        let Value::Object(map) = self.value else {
            return Err(self.error("an object"));
        };
        Ok(map
            .iter()
            .map(|(k, v)| (k.as_str(), self.child(k, v)))
            .collect())
    }

    /// This value as the statistics glassscan writes: `{mean, std, max, n}`, the first three
    /// null when `n` is 0.
    pub fn stats(&self) -> Result<Stats, ReportError> {
        Ok(Stats {
            mean: self.get("mean")?.opt_f64()?,
            std: self.opt("std").map(|s| s.f64()).transpose()?,
            max: self.get("max")?.opt_f64()?,
            n: self.opt("n").map(|n| n.u64()).transpose()?,
        })
    }
}

/// Mean, standard deviation and maximum of an error, as the run recorded them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    /// Mean (None: nothing to average).
    pub mean: Option<f64>,
    /// Standard deviation, where recorded.
    pub std: Option<f64>,
    /// Maximum.
    pub max: Option<f64>,
    /// Sample count, where recorded.
    pub n: Option<u64>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn errors_name_the_file_the_place_and_what_was_expected() {
        let v =
            json!({"angles": [{"scan_angle_deg": "ten"}], "s": {"mean": null, "max": 2.0, "n": 0}});
        let file = Path::new("run/summary.json");
        let root = Node::root(file, &v);
        let angle = &root.get("angles").unwrap().array().unwrap()[0];
        let e = angle.get("scan_angle_deg").unwrap().f64().unwrap_err();
        assert_eq!(
            e.to_string(),
            "run/summary.json: angles[0].scan_angle_deg: expected a number, found a string"
        );
        let e = angle.get("bip_error_mm").unwrap_err();
        assert_eq!(
            e.to_string(),
            "run/summary.json: angles[0]: expected a member \"bip_error_mm\", found none"
        );
        let s = root.get("s").unwrap().stats().unwrap();
        assert_eq!(
            (s.mean, s.max, s.n, s.std),
            (None, Some(2.0), Some(0), None)
        );
        assert!(root.opt("missing").is_none());
        assert!(root.get("angles").unwrap().str().is_err());
    }

    #[test]
    fn a_file_that_does_not_parse_names_line_and_column() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("summary.json");
        std::fs::write(&path, "{\n  \"a\": 1,\n  oops\n}").unwrap();
        let e = read_json_file(&path, "a study summary")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("summary.json: line 3 column 3: expected a study summary (JSON)"),
            "{e}"
        );
        let e = read_json_file(&dir.path().join("none.json"), "x")
            .unwrap_err()
            .to_string();
        assert!(e.contains("none.json: could not read x"), "{e}");
    }
}
