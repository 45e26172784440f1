//! One colour per method variant across every chart of a report: a variant's palette index is
//! the order in which its label first appears among the report's runs, so the wavefront is the
//! same colour in error-vs-time, SIMD, speed-vs-memory and crossover, and the page draws one
//! legend for all of them ([`MethodColours::legend`]).

use std::cell::RefCell;

use super::report::ExperimentReport;

/// Labels in order of first appearance; names no label claims get the indices after them, in
/// the order they are first asked for (the shading-cost chart's parity line, say).
pub struct MethodColours {
    labels: Vec<String>,
    others: RefCell<Vec<String>>,
}

impl MethodColours {
    pub fn of(report: &ExperimentReport) -> Self {
        let mut labels: Vec<String> = Vec::new();
        for r in &report.runs {
            if !labels.contains(&r.label) {
                labels.push(r.label.clone());
            }
        }
        MethodColours { labels, others: RefCell::new(Vec::new()) }
    }

    /// The palette index of a series or bar named `name`: its label's, where the name is a
    /// label, a label followed by the settings that tell series apart (`wavefront 16spp`,
    /// `megakernel d8 NEE`), or a label with the swept knob taken out (`wavefront` for
    /// `wavefront pool=4096`); the longest such label wins.
    pub fn index(&self, name: &str) -> usize {
        let claims = |l: &&String| {
            name == l.as_str()
                || name.strip_prefix(l.as_str()).is_some_and(|rest| rest.starts_with(' '))
                || l.strip_prefix(name).is_some_and(|rest| rest.starts_with(' '))
        };
        let best = self.labels.iter().enumerate().filter(|(_, l)| claims(l)).max_by_key(|(_, l)| l.len());
        if let Some((i, _)) = best {
            return i;
        }
        let mut others = self.others.borrow_mut();
        let k = match others.iter().position(|o| o == name) {
            Some(k) => k,
            None => {
                others.push(name.to_string());
                others.len() - 1
            }
        };
        self.labels.len() + k
    }

    /// The colour function a chart takes ([`crate::chart::ColourOf`]).
    pub fn get(&self, name: &str) -> Option<usize> {
        Some(self.index(name))
    }

    /// Every method variant with its colour (`#rrggbb`), in the report's order: the page's
    /// shared legend.
    pub fn legend(&self) -> Vec<(String, String)> {
        self.labels
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let c = crate::chart::color(i);
                (l.clone(), crate::chart::hex([c.0, c.1, c.2]))
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_series_takes_its_methods_colour() {
        let c = MethodColours {
            labels: ["cpu", "megakernel", "megakernel-regenerate", "wavefront pool=4096"]
                .map(String::from)
                .into(),
            others: RefCell::new(Vec::new()),
        };
        assert_eq!(c.index("megakernel"), 1);
        assert_eq!(c.index("megakernel 16spp"), 1);
        assert_eq!(c.index("megakernel-regenerate 4spp"), 2, "not the shorter megakernel");
        assert_eq!(c.index("wavefront"), 3, "the swept knob taken out");
        assert_eq!(c.index("parity (1×)"), 4);
        assert_eq!(c.index("something else"), 5);
        assert_eq!(c.index("parity (1×)"), 4, "the same name keeps its colour");
    }
}
