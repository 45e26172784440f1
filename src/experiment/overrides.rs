//! `experiment run --set KEY=VALUE`: changes a config from the command line without copying it
//! (a copy elsewhere would break its relative scene paths). KEY is a dotted path into the
//! config's JSON (`spp`, `warmup.min_seconds`, `methods.1.threads`: a number steps into an
//! array); VALUE is JSON (`[4, 16]`, `true`, `{"max_frames": 2}`), or else taken as a string
//! (`scenes.0=cornell`). The result is validated as the file's fields are, and an error at a
//! field that was set names the `--set` that set it. The report records the overrides beside the
//! effective config.

use serde_json::Value;

/// One `--set KEY=VALUE`.
#[derive(Clone, Debug, PartialEq)]
pub struct Override {
    /// The argument as given, for the report and for error messages.
    pub text: String,
    pub keys: Vec<String>,
    pub value: Value,
}

impl Override {
    /// Parses `KEY=VALUE` (`--set`'s value parser).
    pub fn parse(arg: &str) -> Result<Self, String> {
        let Some((key, value)) = arg.split_once('=') else {
            return Err(format!("expected KEY=VALUE (e.g. spp=[4] or methods.0.threads=65536), got {arg:?}"));
        };
        let keys: Vec<String> = key.split('.').map(str::to_owned).collect();
        if keys.iter().any(String::is_empty) {
            return Err(format!("{key:?} is not a dotted path of field names and array indices"));
        }
        // Not JSON: a bare word is meant as a string.
        let value = serde_json::from_str(value).unwrap_or_else(|_| Value::String(value.to_owned()));
        Ok(Self { text: arg.to_owned(), keys, value })
    }

    /// The path as the config's errors write it (`methods[1].threads`).
    pub fn path(&self) -> String {
        let mut out = String::new();
        for k in &self.keys {
            if k.parse::<usize>().is_ok() {
                out.push_str(&format!("[{k}]"));
            } else {
                out = crate::strict_json::join(&out, k);
            }
        }
        out
    }

    /// Sets the value in `config`: every step but the last must exist (an object's field or an
    /// array's index); the last may add a field, which validation then checks like any other.
    pub fn apply(&self, config: &mut Value) -> Result<(), String> {
        let (last, steps) = self.keys.split_last().expect("parse refuses an empty key");
        let mut at = config;
        let mut path = String::new();
        for k in steps {
            at = step(at, k, &path)?;
            path = if k.parse::<usize>().is_ok() {
                format!("{path}[{k}]")
            } else {
                crate::strict_json::join(&path, k)
            };
        }
        match at {
            Value::Object(map) => {
                map.insert(last.clone(), self.value.clone());
                Ok(())
            }
            Value::Array(items) => {
                let i = index(last, items.len(), &path)?;
                items[i] = self.value.clone();
                Ok(())
            }
            other => Err(format!(
                "{} is {}, not an object or array",
                where_(&path),
                crate::strict_json::describe(other)
            )),
        }
    }
}

fn where_(path: &str) -> String {
    if path.is_empty() {
        "the config".into()
    } else {
        format!("\"{path}\"")
    }
}

fn index(key: &str, len: usize, path: &str) -> Result<usize, String> {
    match key.parse::<usize>() {
        Ok(i) if i < len => Ok(i),
        Ok(i) => Err(format!("{} has {len} entries, so no index {i}", where_(path))),
        Err(_) => Err(format!("{} is an array: step into it with an index, not {key:?}", where_(path))),
    }
}

fn step<'v>(at: &'v mut Value, key: &str, path: &str) -> Result<&'v mut Value, String> {
    if let Value::Object(map) = &*at {
        if !map.contains_key(key) {
            // The config's own fields, and at the top the fields it may have but leaves out.
            let mut fields: Vec<&str> = map.keys().map(String::as_str).collect();
            if path.is_empty() {
                fields.extend(super::config::TOP_FIELDS);
            }
            let hint = crate::strict_json::did_you_mean(key, &fields);
            return Err(format!("{} has no field {key:?} to step into{hint}", where_(path)));
        }
    }
    match at {
        Value::Object(map) => Ok(map.get_mut(key).expect("checked above")),
        Value::Array(items) => {
            let i = index(key, items.len(), path)?;
            Ok(&mut items[i])
        }
        other => Err(format!(
            "{} is {}, not an object or array",
            where_(path),
            crate::strict_json::describe(other)
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn sets_fields_array_entries_and_strings() {
        let mut c = json!({"spp": [4], "warmup": {"agree": 0.05}, "methods": [{"method": "cpu"}, {"method": "megakernel"}]});
        for arg in
            ["spp=[1, 2]", "warmup.max_frames=3", "methods.1.threads=65536", "methods.0.method=cpu-f64"]
        {
            Override::parse(arg).unwrap().apply(&mut c).unwrap();
        }
        assert_eq!(
            c,
            json!({"spp": [1, 2], "warmup": {"agree": 0.05, "max_frames": 3},
                   "methods": [{"method": "cpu-f64"}, {"method": "megakernel", "threads": 65536}]})
        );
        assert_eq!(Override::parse("methods.1.threads=1").unwrap().path(), "methods[1].threads");
    }

    #[test]
    fn bad_overrides_say_why() {
        assert!(Override::parse("spp").unwrap_err().contains("KEY=VALUE"));
        assert!(Override::parse("methods..x=1").unwrap_err().contains("dotted path"));
        let mut c = json!({"spp": [4], "methods": [{"method": "cpu"}]});
        let e = |arg: &str, c: &mut Value| Override::parse(arg).unwrap().apply(c).unwrap_err();
        assert!(e("methods.3.threads=1", &mut c).contains("\"methods\" has 1 entries, so no index 3"));
        assert!(e("methods.x.threads=1", &mut c).contains("step into it with an index"));
        assert!(e("warmup.agree=1", &mut c).contains("no field \"warmup\""));
        assert!(e("spp.0.x=1", &mut c).contains("a number (4), not an object or array"));
    }
}
