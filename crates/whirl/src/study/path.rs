//! Parameters addressed by their path in the model file, and set by editing the file's text.
//!
//! A path names a value as the model file writes it: table keys separated by dots, and a
//! selector in brackets after an array of tables (`[[roller_bearing]]`):
//!
//! ```text
//! roller_bearing[*].clearance          every roller bearing
//! roller_bearing[0].rollers            the first one
//! roller_bearing["bearing A"].rollers  the one whose `name` is "bearing A"
//! unbalance[0].eccentricity
//! damping.alpha
//! roller_bearing[1].forcing_function.a0
//! ```
//!
//! Setting a value edits the TOML document (keeping its comments and layout) and leaves the
//! checking to the model's own validation: a study never builds a model any other way than
//! from a model file's text, so a bad value gets exactly the message it would get in the
//! file.

use toml_edit::{Item, TableLike, Value};

/// Which entries of an array of tables a path segment selects.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Selector {
    /// Every entry: `[*]`.
    All,
    /// The entry at this 0-based position: `[0]`.
    Index(usize),
    /// The entry whose `name` is this: `["bearing A"]` (quotes optional).
    Name(String),
}

/// One segment of a path: a key, and a selector when the key holds an array of tables.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Segment {
    /// The table key.
    pub key: String,
    /// The entries selected, for an array of tables.
    pub selector: Option<Selector>,
}

/// A parsed parameter path such as `roller_bearing[*].clearance`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParameterPath {
    /// The segments from the file's top level.
    pub segments: Vec<Segment>,
}

impl std::fmt::Display for ParameterPath {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (i, s) in self.segments.iter().enumerate() {
            if i > 0 {
                f.write_str(".")?;
            }
            f.write_str(&s.key)?;
            match &s.selector {
                None => {}
                Some(Selector::All) => f.write_str("[*]")?,
                Some(Selector::Index(k)) => write!(f, "[{k}]")?,
                Some(Selector::Name(n)) => write!(f, "[\"{n}\"]")?,
            }
        }
        Ok(())
    }
}

/// The help shown with every malformed path.
pub const PATH_HELP: &str = "write the path as in the model file: keys separated by dots, and \
    after an array of tables a selector, e.g. `roller_bearing[*].clearance` (every roller \
    bearing), `roller_bearing[0].rollers`, `roller_bearing[\"bearing A\"].rollers`, \
    `unbalance[0].eccentricity`, `damping.alpha`";

impl ParameterPath {
    /// Parses a path; the error says what is wrong with it.
    ///
    /// # Errors
    /// A message for an empty path or key, a `]` without `[`, an unclosed `[` or quote, or an
    /// empty selector.
    pub fn parse(text: &str) -> Result<ParameterPath, String> {
        let mut segments = Vec::new();
        for part in split_outside_brackets(text.trim())? {
            segments.push(parse_segment(&part)?);
        }
        if segments.is_empty() {
            return Err("the path is empty".into());
        }
        if segments.last().is_some_and(|s| s.selector.is_some()) {
            return Err(format!(
                "`{text}` ends in a selector; a path must end at a value, e.g. `{}.clearance`",
                text.trim()
            ));
        }
        Ok(ParameterPath { segments })
    }

    /// The first key (`cascade` for a study's cascade settings, else a model table).
    pub fn root(&self) -> &str {
        &self.segments[0].key
    }

    /// Sets the value at this path in `table` to `value` in every selected entry; returns
    /// how many values were set. The last key is added when it is missing (the model's
    /// validation then says whether it may be there).
    ///
    /// # Errors
    /// A message naming the path when a key is missing on the way, a selector matches nothing,
    /// or a table is not where the path expects one.
    pub fn set(&self, table: &mut dyn TableLike, value: &Value) -> Result<usize, String> {
        set_in(table, &self.segments, value, "")
    }
}

/// Splits at the dots that are not inside brackets or quotes.
fn split_outside_brackets(text: &str) -> Result<Vec<String>, String> {
    let mut parts = vec![String::new()];
    let (mut depth, mut quote) = (0, None);
    for c in text.chars() {
        match (c, quote) {
            ('"' | '\'', None) if depth > 0 => quote = Some(c),
            (q, Some(open)) if q == open => quote = None,
            (_, Some(_)) => {}
            ('[', None) => depth += 1,
            (']', None) if depth == 0 => return Err(format!("`{text}` has a `]` without `[`")),
            (']', None) => depth -= 1,
            ('.', None) if depth == 0 => {
                parts.push(String::new());
                continue;
            }
            _ => {}
        }
        if let Some(last) = parts.last_mut() {
            last.push(c);
        }
    }
    if depth != 0 || quote.is_some() {
        return Err(format!("`{text}` has an unclosed `[` or quote"));
    }
    Ok(parts)
}

/// `key` or `key[selector]`.
fn parse_segment(part: &str) -> Result<Segment, String> {
    let (key, selector) = match part.split_once('[') {
        None => (part, None),
        Some((key, rest)) => {
            let inner = rest
                .strip_suffix(']')
                .ok_or_else(|| format!("`{part}`: nothing may follow the `]`"))?;
            (key, Some(parse_selector(inner.trim())?))
        }
    };
    let bare = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
    if key.is_empty() || !key.chars().all(bare) {
        return Err(format!(
            "`{part}` is not a key: keys are letters, digits, `_` and `-`"
        ));
    }
    Ok(Segment {
        key: key.to_string(),
        selector,
    })
}

fn parse_selector(inner: &str) -> Result<Selector, String> {
    if inner == "*" {
        return Ok(Selector::All);
    }
    if let Ok(k) = inner.parse::<usize>() {
        return Ok(Selector::Index(k));
    }
    let unquoted = [('"', '"'), ('\'', '\'')]
        .iter()
        .find_map(|(a, b)| inner.strip_prefix(*a)?.strip_suffix(*b))
        .unwrap_or(inner);
    if unquoted.is_empty() {
        return Err("an empty selector `[]`: give `[*]`, `[0]` or `[\"name\"]`".into());
    }
    Ok(Selector::Name(unquoted.to_string()))
}

/// Walks `segments` from `table`, setting `value` at the end; `done` is the path so far,
/// for messages.
fn set_in(
    table: &mut dyn TableLike,
    segments: &[Segment],
    value: &Value,
    done: &str,
) -> Result<usize, String> {
    let Some((first, rest)) = segments.split_first() else {
        return Ok(0);
    };
    let here = if done.is_empty() {
        first.key.clone()
    } else {
        format!("{done}.{}", first.key)
    };
    if rest.is_empty() {
        table.insert(&first.key, Item::Value(value.clone()));
        return Ok(1);
    }
    let Some(item) = table.get_mut(&first.key) else {
        return Err(missing_key(&here, &*table));
    };
    match &first.selector {
        None => {
            if entries(item).is_some() {
                return Err(format!(
                    "`{here}` is a list of tables: say which with `{here}[*]` (all), \
                     `{here}[0]` or `{here}[\"name\"]`"
                ));
            }
            let inner = item
                .as_table_like_mut()
                .ok_or_else(|| format!("`{here}` is a value, not a table"))?;
            set_in(inner, rest, value, &here)
        }
        Some(selector) => {
            let list = entries(item).ok_or_else(|| {
                format!("`{here}` is not a list of tables: drop the selector after it")
            })?;
            let chosen = select(list, selector, &here)?;
            let mut count = 0;
            for entry in chosen {
                count += set_in(entry, rest, value, &here)?;
            }
            Ok(count)
        }
    }
}

fn missing_key(here: &str, table: &dyn TableLike) -> String {
    let keys: Vec<&str> = table.iter().map(|(k, _)| k).collect();
    format!(
        "the file has no `{here}`; the keys there are: {}",
        keys.join(", ")
    )
}

/// The entries of an array of tables, written `[[key]]` or as an array of inline tables.
fn entries(item: &mut Item) -> Option<Vec<&mut dyn TableLike>> {
    match item {
        Item::ArrayOfTables(a) => Some(a.iter_mut().map(|t| t as &mut dyn TableLike).collect()),
        Item::Value(Value::Array(a)) if a.iter().all(|v| v.is_inline_table()) && !a.is_empty() => {
            Some(
                a.iter_mut()
                    .filter_map(|v| v.as_inline_table_mut())
                    .map(|t| t as &mut dyn TableLike)
                    .collect(),
            )
        }
        _ => None,
    }
}

/// The entries a selector picks; an error when it picks none.
fn select<'a>(
    list: Vec<&'a mut dyn TableLike>,
    selector: &Selector,
    here: &str,
) -> Result<Vec<&'a mut dyn TableLike>, String> {
    let n = list.len();
    match selector {
        Selector::All => Ok(list),
        Selector::Index(k) => list.into_iter().nth(*k).map(|e| vec![e]).ok_or_else(|| {
            format!(
                "`{here}[{k}]`: the file has {n} of them, numbered from 0 to {}",
                n - 1
            )
        }),
        Selector::Name(name) => {
            let names: Vec<String> = list.iter().filter_map(|e| entry_name(&**e)).collect();
            let chosen: Vec<_> = list
                .into_iter()
                .filter(|e| entry_name(&**e).as_deref() == Some(name.as_str()))
                .collect();
            if chosen.is_empty() {
                return Err(format!(
                    "no `{here}` is named \"{name}\"; the names are: {}",
                    if names.is_empty() {
                        "(none has a name: select by number, e.g. [0])".to_string()
                    } else {
                        names.join(", ")
                    }
                ));
            }
            Ok(chosen)
        }
    }
}

fn entry_name(entry: &dyn TableLike) -> Option<String> {
    entry
        .get("name")
        .and_then(|n| n.as_str())
        .map(str::to_string)
}

#[cfg(test)]
mod tests {
    use super::*;
    use toml_edit::DocumentMut;

    #[test]
    fn parses_keys_indices_names_and_wildcards() {
        let p = ParameterPath::parse("roller_bearing[\"bearing.A\"].forcing_function.a0").unwrap();
        assert_eq!(p.segments.len(), 3);
        assert_eq!(
            p.segments[0].selector,
            Some(Selector::Name("bearing.A".into()))
        );
        assert_eq!(
            p.to_string(),
            "roller_bearing[\"bearing.A\"].forcing_function.a0"
        );
        let p = ParameterPath::parse("roller_bearing[*].clearance").unwrap();
        assert_eq!(p.segments[0].selector, Some(Selector::All));
        assert!(ParameterPath::parse("roller_bearing[0]").is_err());
        assert!(ParameterPath::parse("roller_bearing[0.clearance").is_err());
        assert!(ParameterPath::parse("a..b").is_err());
    }

    #[test]
    fn sets_exactly_the_selected_values_and_keeps_the_rest_of_the_text() {
        let text = "# a comment\n[[b]]\nname = \"A\"\nc = 1\n[[b]]\nname = \"B\"\nc = 1\n";
        let set = |path: &str| {
            let mut doc: DocumentMut = text.parse().unwrap();
            let n = ParameterPath::parse(path)
                .unwrap()
                .set(doc.as_table_mut(), &Value::from(7))
                .unwrap();
            (n, doc.to_string())
        };
        let (n, out) = set("b[\"B\"].c");
        assert_eq!(n, 1);
        assert_eq!(out, text.replace("\"B\"\nc = 1", "\"B\"\nc = 7"));
        let (n, out) = set("b[*].c");
        assert_eq!(n, 2);
        assert_eq!(out.matches("c = 7").count(), 2);
        assert!(out.starts_with("# a comment\n"));
    }

    #[test]
    fn refuses_ambiguous_or_missing_targets_with_the_fix() {
        let mut doc: DocumentMut = "[[b]]\nc = 1\n[d]\ne = 2\n".parse().unwrap();
        let v = Value::from(1);
        let e = |p: &str, doc: &mut DocumentMut| {
            ParameterPath::parse(p)
                .unwrap()
                .set(doc.as_table_mut(), &v)
                .unwrap_err()
        };
        assert!(e("b.c", &mut doc).contains("`b[*]`"));
        assert!(e("b[3].c", &mut doc).contains("has 1 of them"));
        assert!(e("d[0].e", &mut doc).contains("not a list of tables"));
        assert!(e("x.y", &mut doc).contains("keys there are: b, d"));
        assert!(e("b[\"z\"].c", &mut doc).contains("none has a name"));
    }
}
