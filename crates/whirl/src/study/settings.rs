//! The `[cascade]` table of a study: each entry read by the cascade's own request
//! ([`CascadeRequest::set`], as the Python package's keywords are), its errors named
//! `cascade.<field>`.

// Validation runs once per study point; a large error type on this cold path is fine.
#![allow(clippy::result_large_err)]

use crate::error::InputError;
use crate::given::{Given, SetByName};
use crate::nsv::CascadeRequest;

/// Reads a `[cascade]` table; errors name the field as `cascade.<field>`.
///
/// # Errors
/// An [`InputError`] naming `cascade.<field>` for an unknown field or a value it does not
/// read.
pub fn cascade_settings(table: &toml::Table) -> Result<CascadeRequest, InputError> {
    let mut request = CascadeRequest::default();
    for (name, value) in table {
        let in_table = |mut e: InputError| {
            e.field = Some(format!("cascade.{name}"));
            e
        };
        let given = Given::try_from(value)
            .map_err(|why| in_table(InputError::field(name, why).help("docs/study-file.md")))?;
        request.set(name, &given).map_err(in_table)?;
    }
    Ok(request)
}
