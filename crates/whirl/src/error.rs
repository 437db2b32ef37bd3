//! Errors of the whirl library.
//!
//! Input errors name the file, line and column, the field and what was expected, so the
//! CLI can show them as they are; numerical failures say what failed and what to change.

use std::ops::Range;
use std::path::PathBuf;

/// An error in a model file or in an analysis option, located in its source text.
#[derive(Debug, Clone, PartialEq)]
pub struct InputError {
    /// The file, when the input came from one.
    pub file: Option<PathBuf>,
    /// The field, as a path (`disk[0].mass`), when one is to blame.
    pub field: Option<String>,
    /// What is wrong and what was expected.
    pub message: String,
    /// How to fix it, when that is not obvious from the message.
    pub help: Option<String>,
    /// Byte range in the source text.
    pub span: Option<Range<usize>>,
    /// 1-based line and column of the span's start.
    pub line_column: Option<(usize, usize)>,
}

impl InputError {
    /// An error about a field, without a place in a file yet.
    pub fn field(field: impl Into<String>, message: impl Into<String>) -> Self {
        InputError {
            file: None,
            field: Some(field.into()),
            message: message.into(),
            help: None,
            span: None,
            line_column: None,
        }
    }

    /// Adds the byte span of the offending value.
    pub fn at(mut self, span: Range<usize>) -> Self {
        self.span = Some(span);
        self
    }

    /// Adds a hint on how to fix it.
    pub fn help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }

    /// Fills in file, line and column from the source text.
    pub fn locate(mut self, file: Option<PathBuf>, source: &str) -> Self {
        self.file = file;
        if let Some(span) = &self.span {
            self.line_column = Some(line_column(source, span.start));
        }
        self
    }
}

/// 1-based line and column (in characters) of a byte offset.
pub fn line_column(source: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(source.len());
    let before = source.get(..offset).unwrap_or(source);
    let line = before.matches('\n').count() + 1;
    let column = before
        .rsplit('\n')
        .next()
        .map(|l| l.chars().count())
        .unwrap_or(0)
        + 1;
    (line, column)
}

impl std::fmt::Display for InputError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if let Some(file) = &self.file {
            write!(f, "{}", file.display())?;
            if let Some((l, c)) = self.line_column {
                write!(f, ":{l}:{c}")?;
            }
            write!(f, ": ")?;
        } else if let Some((l, c)) = self.line_column {
            write!(f, "line {l}, column {c}: ")?;
        }
        if let Some(field) = &self.field {
            write!(f, "`{field}`: ")?;
        }
        write!(f, "{}", self.message)?;
        if let Some(help) = &self.help {
            write!(f, "\n  help: {help}")?;
        }
        Ok(())
    }
}

impl std::error::Error for InputError {}

/// Everything that can go wrong in whirl.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The model file or an option is wrong.
    #[error("{0}")]
    Input(Box<InputError>),
    /// A file could not be read or written.
    #[error("cannot {action} `{path}`: {source}")]
    Io {
        /// What was being done, e.g. "read the model file".
        action: &'static str,
        /// The file or folder.
        path: PathBuf,
        /// The system's reason.
        source: std::io::Error,
    },
    /// An option or argument of an analysis is out of its range: an empty or unsorted
    /// speed list, a step that is not positive, a DOF or node outside the model, a signal
    /// too short or not finite. The message names the value and the range.
    #[error("{0}")]
    InvalidOption(String),
    /// The analysis does not support this combination of model, method and options (for
    /// example Lagrange-multiplier contacts with an implicit method, or an unbalance
    /// response of a model without unbalance). The message says what to use instead.
    #[error("{0}")]
    Unsupported(String),
    /// A matrix that must be inverted is singular (or not positive definite): the
    /// structure is not held, or a frequency sits on a resonance.
    #[error("{message}")]
    Singular {
        /// The matrix, e.g. "mass matrix", "dynamic stiffness", "Jacobian".
        what: &'static str,
        /// What is singular, why, and what to change.
        message: String,
    },
    /// An iterative method stopped before meeting its tolerance.
    #[error("{message}")]
    NotConverged {
        /// The method, e.g. "harmonic balance", "eigen-solver", "static equilibrium".
        what: &'static str,
        /// Iterations made, when the method counts them.
        iterations: Option<usize>,
        /// The last residual (in the method's own measure), when it has one.
        residual: Option<f64>,
        /// What did not converge, where, and what to change.
        message: String,
    },
    /// A time integration diverged; what was computed before stays with the caller.
    #[error("{message}")]
    Diverged {
        /// Time of divergence, s; NaN when several runs diverged (every speed of a cascade).
        time: f64,
        /// The coordinate that left the bound; `usize::MAX` when several runs diverged.
        coordinate: usize,
        /// What happened and what to change.
        message: String,
    },
    /// A result could not be encoded as JSON to be saved.
    #[error("cannot encode {what}: {source}")]
    Encode {
        /// What was being encoded, e.g. "the study manifest".
        what: String,
        /// serde_json's reason.
        source: serde_json::Error,
    },
    /// A part of whirl stopped unexpectedly (a worker thread ended early); a bug to report.
    #[error("{0}")]
    Internal(String),
    /// A long computation was stopped on request; what was finished is kept where the
    /// message says.
    #[error("{0}")]
    Interrupted(String),
}

impl Error {
    /// A singular matrix, named by `what`.
    pub(crate) fn singular(what: &'static str, message: String) -> Error {
        Error::Singular { what, message }
    }

    /// An iteration of method `what` that stopped short of its tolerance.
    pub(crate) fn not_converged(
        what: &'static str,
        iterations: Option<usize>,
        residual: Option<f64>,
        message: String,
    ) -> Error {
        Error::NotConverged {
            what,
            iterations,
            residual,
            message,
        }
    }

    /// The same numerical failure with its message rewritten by `f` (to add where or why it
    /// happened); input, file, divergence, encoding and interruption errors pass unchanged.
    pub(crate) fn map_message(self, f: impl FnOnce(String) -> String) -> Error {
        match self {
            Error::InvalidOption(m) => Error::InvalidOption(f(m)),
            Error::Unsupported(m) => Error::Unsupported(f(m)),
            Error::Singular { what, message } => Error::Singular {
                what,
                message: f(message),
            },
            Error::NotConverged {
                what,
                iterations,
                residual,
                message,
            } => Error::NotConverged {
                what,
                iterations,
                residual,
                message: f(message),
            },
            Error::Internal(m) => Error::Internal(f(m)),
            other => other,
        }
    }
}

impl From<InputError> for Error {
    fn from(e: InputError) -> Self {
        Error::Input(Box::new(e))
    }
}

/// Result with whirl's error.
pub type Result<T> = std::result::Result<T, Error>;

/// Maps an I/O error on `path` to whirl's error, saying what was being done.
pub(crate) fn io<'a>(
    action: &'static str,
    path: &'a std::path::Path,
) -> impl FnOnce(std::io::Error) -> Error + 'a {
    move |source| Error::Io {
        action,
        path: path.to_path_buf(),
        source,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_column_are_one_based() {
        let src = "a = 1\nbb = -2\n";
        assert_eq!(line_column(src, 0), (1, 1));
        assert_eq!(line_column(src, src.find("-2").unwrap()), (2, 6));
    }
}
