//! Errors as the user sees them: miette diagnostics.
//!
//! A [`whirl::InputError`] becomes a diagnostic whose message starts with
//! `file:line:column: `field`:` (so it can be read, grepped and clicked without the
//! snippet), with the model file's offending line underlined and the library's help.

use std::fmt;

use miette::{Diagnostic, LabeledSpan, NamedSource, SourceCode, SourceSpan};

/// The longest line (in bytes) shown under a message. miette cannot draw a label past
/// column 65,535 (it panics), and a line of thousands of characters shows nothing a person
/// can read: the message's `file:line:column` locates such an error on its own.
const MAX_SHOWN_LINE: usize = 1000;

/// Sets up miette's report style: long lines are wrapped, but never inside a word (a path
/// with its line and column must stay whole), and no terminal hyperlinks.
pub fn install_hook() {
    let _ = miette::set_hook(Box::new(|_| {
        Box::new(
            miette::MietteHandlerOpts::new()
                .terminal_links(false)
                .break_words(false)
                .width(100)
                .build(),
        )
    }));
}

/// A diagnostic: message, optional help and optional place in a source text.
#[derive(Debug)]
pub struct Diag {
    message: String,
    help: Option<String>,
    source: Option<NamedSource<String>>,
    span: Option<SourceSpan>,
    label: String,
}

impl Diag {
    /// A plain message.
    pub fn new(message: impl Into<String>) -> Self {
        Diag {
            message: message.into(),
            help: None,
            source: None,
            span: None,
            label: String::new(),
        }
    }

    /// The same diagnostic with a hint on how to fix it.
    pub fn help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }

    /// A bad command-line option: "invalid `--speeds`: why".
    pub fn option(option: &str, why: impl fmt::Display) -> Self {
        Diag::new(format!("invalid `{option}`: {why}"))
    }

    /// An error in a model file, located in `text` when it has a span.
    pub fn input(e: &whirl::InputError, text: &str) -> Self {
        // Errors of the TOML syntax and types come without a field: name the key whose value
        // is at fault, and say the expected type in words.
        let field = e
            .field
            .clone()
            .or_else(|| e.span.as_ref().and_then(|s| key_before(text, s.start)));
        let message = e
            .message
            .replace("expected i64", "expected a whole number")
            .replace("expected f64", "expected a number");
        let located = whirl::InputError {
            help: None,
            field,
            message,
            ..e.clone()
        };
        let name = e
            .file
            .as_ref()
            .map(|f| f.display().to_string())
            .unwrap_or_else(|| "model".into());
        // Clamp the span into the text: a diagnostic must render even if a span is off.
        let span = e
            .span
            .as_ref()
            .filter(|_| !text.is_empty())
            .map(|s| {
                let start = s.start.min(text.len().saturating_sub(1));
                let end = s.end.clamp(start, text.len());
                start..end
            })
            .filter(|s| showable(text, s))
            .map(SourceSpan::from);
        Diag {
            message: located.to_string(),
            help: e.help.clone(),
            source: span.map(|_| NamedSource::new(name, text.to_string())),
            span,
            label: located.field.clone().unwrap_or_else(|| "here".into()),
        }
    }
}

/// True when every line the diagnostic prints is short enough to show (see
/// [`MAX_SHOWN_LINE`]): the lines the span touches and, as context, one on either side
/// (miette's default), so that a 2 MB line next to an error is not echoed whole.
fn showable(text: &str, span: &std::ops::Range<usize>) -> bool {
    let bytes = text.as_bytes();
    let line_start = |at: usize| {
        bytes[..at]
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |i| i + 1)
    };
    let line_end = |at: usize| {
        bytes[at..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(text.len(), |i| at + i)
    };
    let first = line_start(span.start);
    let start = line_start(first.saturating_sub(1));
    let last = line_end(span.end);
    let end = line_end((last + 1).min(text.len()));
    text[start..end].lines().all(|l| l.len() <= MAX_SHOWN_LINE)
}

/// The key of a `key = value` line when `offset` falls in its value, e.g. `elements`.
fn key_before(text: &str, offset: usize) -> Option<String> {
    let before = text.get(..offset.min(text.len()))?;
    let line = before.rsplit('\n').next()?;
    let (key, _) = line.split_once('=')?;
    let key = key.trim();
    let bare = |c: char| c.is_ascii_alphanumeric() || "_-.\"".contains(c);
    (!key.is_empty() && key.chars().all(bare)).then(|| key.to_string())
}

impl fmt::Display for Diag {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Diag {}

impl Diagnostic for Diag {
    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.help
            .as_ref()
            .map(|h| Box::new(h) as Box<dyn fmt::Display>)
    }

    fn source_code(&self) -> Option<&dyn SourceCode> {
        self.source.as_ref().map(|s| s as &dyn SourceCode)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        let span = self.span?;
        let label = LabeledSpan::new_with_span(Some(self.label.clone()), span);
        Some(Box::new(std::iter::once(label)))
    }
}

/// A library error as a report; `text` is the model file's text, for input errors.
pub fn from_whirl(e: whirl::Error, text: &str) -> miette::Report {
    match &e {
        whirl::Error::Input(input) => Diag::input(input, text).into(),
        // I/O and numerical failures carry their own complete message.
        _ => Diag::new(e.to_string()).into(),
    }
}
