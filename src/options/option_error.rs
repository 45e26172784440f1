//! A knob set to a value its method cannot run: out of its range, or set where it would change
//! nothing. The command line, experiment configs, the replay and the renderers all get one from
//! [`super::check`]; each words it its own way ([`OptionError::for_cli`],
//! [`OptionError::for_config`]), naming the knob.

/// A knob set to a value its method cannot run.
#[derive(Clone, Debug, PartialEq)]
pub struct OptionError {
    /// The knob at fault, as configs and reports spell it (`tail`; the flag is `--tail`).
    pub knob: &'static str,
    pub problem: Problem,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Problem {
    /// Outside the knob's range: what it must be.
    Range(String),
    /// The value (as written, quoted in configs when `text`) means something only when `other`
    /// is one of `values`: `why` says what it does.
    Needs {
        value: String,
        text: bool,
        why: &'static str,
        other: &'static str,
        values: &'static [&'static str],
    },
}

impl OptionError {
    pub(super) fn range(knob: &'static str, reason: String) -> Self {
        Self { knob, problem: Problem::Range(reason) }
    }

    /// As the command line says it: `--tail megakernel finishes regenerated paths: it needs
    /// --schedule regenerate`.
    pub fn for_cli(&self) -> String {
        self.for_cli_where_regenerating_is("--schedule regenerate")
    }

    /// As [`Self::for_cli`], for a command whose flag for regenerating is another (the replay's
    /// `--methods wavefront-regenerate`).
    pub fn for_cli_where_regenerating_is(&self, regenerating: &str) -> String {
        let flag = |k: &str| format!("--{}", k.replace('_', "-"));
        match &self.problem {
            Problem::Range(r) => format!("{} {r}", flag(self.knob)),
            Problem::Needs { value, why, other, values, .. } => {
                let want = match *other {
                    "schedule" => regenerating.to_owned(),
                    // The command line turns queues on and off with --compaction on|off, and
                    // chooses how they are built with --compaction-method.
                    "compaction" if values == &["atomic"] => {
                        "--compaction on and --compaction-method atomic".to_owned()
                    }
                    "compaction" if values == &["scan"] => {
                        "--compaction on and --compaction-method scan (or --queue-order slot-depth)"
                            .to_owned()
                    }
                    "compaction" => "--compaction on".to_owned(),
                    _ => format!("{} {}", flag(other), values.join(" or ")),
                };
                format!("{} {value} {why}: it needs {want}", flag(self.knob))
            }
        }
    }

    /// As a config says it, at `methods[i].<knob>`: `"megakernel" finishes regenerated paths:
    /// it needs "schedule": "regenerate"`.
    pub fn for_config(&self) -> String {
        match &self.problem {
            Problem::Range(r) => r.clone(),
            Problem::Needs { value, text, why, other, values } => {
                let value = if *text { format!("{value:?}") } else { value.clone() };
                // A number as JSON writes it, a name quoted.
                let want: Vec<String> = values
                    .iter()
                    .map(|v| if v.parse::<f64>().is_ok() { v.to_string() } else { format!("{v:?}") })
                    .collect();
                format!("{value} {why}: it needs \"{other}\": {}", want.join(" or "))
            }
        }
    }

    /// Whether the value is wrong in itself (not only beside another knob's).
    pub fn is_range(&self) -> bool {
        matches!(self.problem, Problem::Range(_))
    }
}

impl std::fmt::Display for OptionError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.for_cli())
    }
}

impl std::error::Error for OptionError {}

/// `knob` in `min..=max` (`unit` after the range in the error).
pub(super) fn in_range(
    knob: &'static str,
    v: u32,
    min: u32,
    max: u32,
    unit: &str,
) -> Result<(), OptionError> {
    if !(min..=max).contains(&v) {
        return Err(OptionError::range(knob, format!("must be in {min}..={max}{unit}, got {v}")));
    }
    Ok(())
}

/// `knob` in (0, 1] (`what`: what the fraction is of).
pub(super) fn fraction(knob: &'static str, v: f64, what: &str) -> Result<(), OptionError> {
    if !(v > 0.0 && v <= 1.0) {
        return Err(OptionError::range(knob, format!("must be {what} in (0, 1], got {v}")));
    }
    Ok(())
}
