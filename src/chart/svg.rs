//! A minimal SVG writer that keeps its output well-formed: elements are closed in the order they
//! were opened, and every text node and attribute value goes through [`escape`].

use std::fmt::Write as _;

/// Escapes `s` for use as XML element text or as a double-quoted attribute value.
///
/// Control characters that XML 1.0 forbids even as character references are dropped, so a
/// stray byte in a series name cannot make the whole document unparsable.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            '\t' | '\n' | '\r' => out.push(c),
            c if (c as u32) < 0x20 || c == '\u{FFFE}' || c == '\u{FFFF}' => {}
            c => out.push(c),
        }
    }
    out
}

/// Formats a coordinate or length with at most two decimals (a hundredth of a pixel is far
/// below what a screen shows, and it keeps documents small).
///
/// Callers only pass finite values; should one slip through, it becomes `0` so the document
/// never contains `NaN` or `inf`.
pub fn num(v: f64) -> String {
    debug_assert!(v.is_finite(), "non-finite SVG coordinate {v}");
    if !v.is_finite() {
        return "0".to_string();
    }
    let s = format!("{v:.2}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

/// A value that can be written as an attribute.
pub trait AttrValue {
    fn write_to(&self, out: &mut String);
}

impl AttrValue for f64 {
    fn write_to(&self, out: &mut String) {
        out.push_str(&num(*self));
    }
}

impl AttrValue for &str {
    fn write_to(&self, out: &mut String) {
        out.push_str(&escape(self));
    }
}

impl AttrValue for String {
    fn write_to(&self, out: &mut String) {
        out.push_str(&escape(self));
    }
}

/// Accumulates an SVG (or any XML) document.
#[derive(Debug, Default)]
pub struct SvgWriter {
    out: String,
    open: Vec<&'static str>,
}

impl SvgWriter {
    pub fn new() -> Self {
        Self::default()
    }

    /// Starts an element; finish it with [`Tag::empty`], [`Tag::text`] or [`Tag::open`].
    pub fn tag(&mut self, name: &'static str) -> Tag<'_> {
        self.out.push('<');
        self.out.push_str(name);
        Tag { w: self, name }
    }

    /// Closes the innermost element opened with [`Tag::open`].
    pub fn close(&mut self) {
        let name = self.open.pop().expect("SvgWriter::close without an open element");
        let _ = writeln!(self.out, "</{name}>");
    }

    /// Closes every element still open and returns the document.
    pub fn finish(mut self) -> String {
        while !self.open.is_empty() {
            self.close();
        }
        self.out
    }
}

/// An element whose start tag is being written.
#[must_use = "finish the element with empty(), text() or open()"]
pub struct Tag<'a> {
    w: &'a mut SvgWriter,
    name: &'static str,
}

impl Tag<'_> {
    pub fn attr(self, key: &str, value: impl AttrValue) -> Self {
        let out = &mut self.w.out;
        out.push(' ');
        out.push_str(key);
        out.push_str("=\"");
        value.write_to(out);
        out.push('"');
        self
    }

    /// Ends the element with no content: `<name .../>`.
    pub fn empty(self) {
        self.w.out.push_str("/>\n");
    }

    /// Ends the element with escaped text content: `<name ...>text</name>`.
    pub fn text(self, text: &str) {
        let _ = writeln!(self.w.out, ">{}</{}>", escape(text), self.name);
    }

    /// Leaves the element open for children; [`SvgWriter::close`] ends it.
    pub fn open(self) {
        self.w.out.push_str(">\n");
        self.w.open.push(self.name);
    }
}
