//! Strict JSON input shared by the file formats people write by hand (scenes, experiment
//! configs): parsing that refuses duplicate keys, and the pieces of error messages that name a
//! JSON path and suggest a fix.

use std::cell::RefCell;
use std::fmt;

use serde::de::{self, DeserializeSeed, MapAccess, SeqAccess, Visitor};
use serde_json::{Map, Value};

// ---------------------------------------------------------------------------------------------
// Parsing: serde_json into a Value, refusing duplicate keys.

/// Where a duplicate key was met, for the error that serde_json then reports with a position.
type DupSlot = RefCell<Option<String>>;

/// Parses JSON like `serde_json::from_str::<Value>`, but a key repeated in one object is an
/// error (with its JSON path) instead of silently keeping the last value. Errors are
/// `(json path, reason)`.
pub(crate) fn parse_strict(text: &str) -> Result<Value, (String, String)> {
    let dup = DupSlot::default();
    let mut de = serde_json::Deserializer::from_str(text);
    let parsed = ValueSeed { path: String::new(), dup: &dup }.deserialize(&mut de).and_then(|v| {
        de.end()?;
        Ok(v)
    });
    parsed.map_err(|e| match dup.take() {
        Some(path) => (path, format!("{e}; each key may appear only once in an object")),
        None => (String::new(), format!("malformed JSON: {e}")),
    })
}

/// Builds a [`Value`] while tracking the JSON path, so a duplicate key can be located.
struct ValueSeed<'a> {
    path: String,
    dup: &'a DupSlot,
}

impl<'de> DeserializeSeed<'de> for ValueSeed<'_> {
    type Value = Value;
    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<Value, D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for ValueSeed<'_> {
    type Value = Value;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("any JSON value")
    }
    fn visit_unit<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }
    fn visit_bool<E>(self, b: bool) -> Result<Value, E> {
        Ok(Value::Bool(b))
    }
    fn visit_i64<E>(self, x: i64) -> Result<Value, E> {
        Ok(x.into())
    }
    fn visit_u64<E>(self, x: u64) -> Result<Value, E> {
        Ok(x.into())
    }
    fn visit_f64<E>(self, x: f64) -> Result<Value, E> {
        // serde_json never yields a non-finite f64 (it rejects out-of-range literals).
        Ok(serde_json::Number::from_f64(x).map_or(Value::Null, Value::Number))
    }
    fn visit_str<E>(self, s: &str) -> Result<Value, E> {
        Ok(Value::String(s.to_owned()))
    }
    fn visit_string<E>(self, s: String) -> Result<Value, E> {
        Ok(Value::String(s))
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        let mut items = Vec::new();
        loop {
            let seed = ValueSeed { path: format!("{}[{}]", self.path, items.len()), dup: self.dup };
            match seq.next_element_seed(seed)? {
                Some(v) => items.push(v),
                None => return Ok(Value::Array(items)),
            }
        }
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Value, A::Error> {
        let mut out = Map::new();
        while let Some(key) = map.next_key::<String>()? {
            let path = join(&self.path, &key);
            if out.contains_key(&key) {
                *self.dup.borrow_mut() = Some(path);
                return Err(de::Error::custom(format_args!("duplicate key {key:?}")));
            }
            let value = map.next_value_seed(ValueSeed { path, dup: self.dup })?;
            out.insert(key, value);
        }
        Ok(Value::Object(out))
    }
}

// ---------------------------------------------------------------------------------------------
// Message helpers.

/// `parent.key`, or `parent["key"]` when the key would not read as a plain name.
pub(crate) fn join(parent: &str, key: &str) -> String {
    let plain = !key.is_empty() && key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    match (parent.is_empty(), plain) {
        (true, true) => key.to_owned(),
        (false, true) => format!("{parent}.{key}"),
        // Debug quoting escapes quotes, backslashes and control characters.
        (_, false) => format!("{parent}[{key:?}]"),
    }
}

/// What a value is, for "expected X, found Y".
pub(crate) fn describe(v: &Value) -> String {
    match v {
        Value::Null => "null".into(),
        Value::Bool(b) => format!("a boolean ({b})"),
        Value::Number(n) => format!("a number ({n})"),
        Value::String(s) if s.chars().count() <= 40 => format!("a string ({s:?})"),
        Value::String(_) => "a string".into(),
        Value::Array(a) if a.len() == 1 => "an array of 1 value".into(),
        Value::Array(a) => format!("an array of {} values", a.len()),
        Value::Object(_) => "an object".into(),
    }
}

/// `"a", "b" or "c"`.
pub(crate) fn quoted_list(items: &[&str]) -> String {
    let quoted: Vec<String> = items.iter().map(|s| format!("{s:?}")).collect();
    match quoted.split_last() {
        None => "nothing".into(),
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
    }
}

/// ` (did you mean "x"?)` when a candidate is a likely typo of `word`.
pub(crate) fn did_you_mean(word: &str, candidates: &[&str]) -> String {
    let best = candidates
        .iter()
        .map(|c| (edit_distance(word, c), *c))
        .filter(|&(d, c)| d <= 2.max(c.chars().count() / 3))
        .min_by_key(|&(d, _)| d);
    best.map_or_else(String::new, |(_, c)| format!(" (did you mean {c:?}?)"))
}

/// Levenshtein distance over chars; inputs are short field and material names.
pub(crate) fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diag = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let next = (diag + usize::from(ca != cb)).min(row[j] + 1).min(row[j + 1] + 1);
            diag = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_quote_keys_that_are_not_plain_names() {
        assert_eq!(join("", "camera"), "camera");
        assert_eq!(join("materials", "red-1_b"), "materials.red-1_b");
        assert_eq!(join("materials", "my mat"), "materials[\"my mat\"]");
        assert_eq!(join("materials", "a.b"), "materials[\"a.b\"]");
        assert_eq!(join("materials", ""), "materials[\"\"]");
    }

    #[test]
    fn edit_distance_counts_single_edits() {
        assert_eq!(edit_distance("radius", "radius"), 0);
        assert_eq!(edit_distance("radus", "radius"), 1);
        assert_eq!(edit_distance("lambertain", "lambertian"), 2);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(did_you_mean("radus", &["center", "radius"]), " (did you mean \"radius\"?)");
        assert_eq!(did_you_mean("zzzzzz", &["center", "radius"]), "");
    }

    #[test]
    fn lists_read_as_english() {
        assert_eq!(quoted_list(&["a"]), "\"a\"");
        assert_eq!(quoted_list(&["a", "b", "c"]), "\"a\", \"b\" or \"c\"");
    }

    #[test]
    fn duplicate_keys_are_found_at_any_depth() {
        let (path, reason) = parse_strict(r#"{"a": {"b": [1, {"c": 1, "c": 2}]}}"#).unwrap_err();
        assert_eq!(path, "a.b[1].c");
        assert!(reason.contains("duplicate key \"c\""), "{reason}");
        assert!(reason.contains("line 1"), "{reason}");
        assert_eq!(parse_strict(r#"{"a": 1, "b": {"a": 2}}"#).unwrap()["b"]["a"], 2);
    }

    #[test]
    fn trailing_text_is_malformed() {
        let (path, reason) = parse_strict("{} x").unwrap_err();
        assert_eq!(path, "");
        assert!(reason.starts_with("malformed JSON: trailing characters"), "{reason}");
    }

    #[test]
    fn deep_nesting_is_an_error_not_a_stack_overflow() {
        let text = "[".repeat(100_000);
        let (_, reason) = parse_strict(&text).unwrap_err();
        assert!(reason.contains("recursion limit"), "{reason}");
    }
}
