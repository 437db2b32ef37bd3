//! The output folder: `summary.json`, CSV tables and plots, written all or nothing.
//!
//! Everything is written into a temporary sibling folder (`.<name>.whirl-tmp-<pid>`) that is
//! renamed onto the requested folder at the end, replacing an earlier result there. If
//! anything fails on the way the temporary folder is removed and the earlier result stays
//! as it was. An existing folder is only replaced when it is empty or holds a
//! `summary.json` (an earlier whirl result): `--out` never deletes someone's documents.
//!
//! One run per output folder at a time: [`lock`] takes `.<name>.whirl-lock` beside the
//! folder before any work (a second run is refused at once, naming the first one's
//! process), and then removes the temporary folders that killed runs left beside it.
//!
//! CSV files have one header row; numbers are written in full precision (shortest text that
//! reads back to the same f64), and a value that does not exist (a branch lost at a speed,
//! a peak without a half-power band) is an empty cell.
//!
//! `.npy` files are NumPy's format version 1.0, written here directly: the magic
//! `\x93NUMPY`, version bytes 1 0, a little-endian u16 header length, a Python dict literal
//! `{'descr': '<f8', 'fortran_order': False, 'shape': (rows, cols), }` padded with spaces
//! and a newline so that the data starts on a multiple of 64 bytes, then the values as
//! little-endian f64 in row-major order. `numpy.load` reads it as a 2-D float64 array.

use std::fs;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use serde_json::Value;
use whirl::report::{Cell, Table};
use whirl_plot::NamedFigure;

use crate::error::{from_whirl, Diag};
use crate::interrupt;

/// A result folder being written.
#[derive(Debug)]
pub struct Output {
    dir: PathBuf,
    tmp: PathBuf,
    files: Vec<String>,
    finished: bool,
}

fn io_error(action: &str, path: &Path, e: std::io::Error) -> Diag {
    Diag::new(format!("cannot {action} `{}`: {e}", path.display()))
}

/// The folder's absolute path and its name.
fn folder_name(dir: &Path) -> miette::Result<(PathBuf, String)> {
    let dir = std::path::absolute(dir).map_err(|e| io_error("resolve", dir, e))?;
    let name = dir
        .file_name()
        .and_then(|n| n.to_str())
        .ok_or_else(|| {
            Diag::option(
                "--out",
                format!("`{}` does not name a folder", dir.display()),
            )
            .help("give a folder such as `out/modal`")
        })?
        .to_string();
    Ok((dir, name))
}

/// Takes the lock of the output folder `dir` for this run (see the module doc) and
/// removes what killed runs left beside it: their temporary and set-aside folders. A `dir`
/// that may not be replaced is refused here, before the run computes anything.
pub fn lock(dir: &Path) -> miette::Result<whirl::lock::RunLock> {
    let (dir, name) = folder_name(dir)?;
    if dir.exists() {
        check_replaceable(&dir)?;
    }
    let parent = dir.parent().unwrap_or(Path::new("/")).to_path_buf();
    fs::create_dir_all(&parent).map_err(|e| io_error("create the folder", &parent, e))?;
    let path = parent.join(format!(".{name}.whirl-lock"));
    let lock = whirl::lock::RunLock::acquire(&path, &dir).map_err(|e| from_whirl(e, ""))?;
    interrupt::remove_on_quit(&path);
    let leftover = |n: &str| {
        [".whirl-tmp-", ".whirl-old-"]
            .iter()
            .any(|kind| n.starts_with(&format!(".{name}{kind}")))
    };
    for entry in fs::read_dir(&parent)
        .map_err(|e| io_error("read", &parent, e))?
        .flatten()
    {
        if entry.file_name().to_str().is_some_and(leftover) {
            let _ = fs::remove_dir_all(entry.path());
        }
    }
    Ok(lock)
}

impl Output {
    /// Starts writing a result folder that will end up at `dir`.
    pub fn begin(dir: &Path) -> miette::Result<Output> {
        let (dir, name) = folder_name(dir)?;
        if dir.exists() {
            check_replaceable(&dir)?;
        }
        let parent = dir.parent().unwrap_or(Path::new("/")).to_path_buf();
        fs::create_dir_all(&parent).map_err(|e| io_error("create the folder", &parent, e))?;
        let tmp = parent.join(format!(".{name}.whirl-tmp-{}", std::process::id()));
        if tmp.exists() {
            // Left over from a crashed run that had the same process id.
            fs::remove_dir_all(&tmp).map_err(|e| io_error("remove", &tmp, e))?;
        }
        fs::create_dir(&tmp).map_err(|e| io_error("create the folder", &tmp, e))?;
        interrupt::remove_on_quit(&tmp);
        Ok(Output {
            dir,
            tmp,
            files: Vec::new(),
            finished: false,
        })
    }

    /// Writes `name` (e.g. `campbell.csv`) with a header row and rows of cells. The rows
    /// may be produced lazily, so a long time history is never held as text in memory.
    pub fn csv<R, C>(
        &mut self,
        name: &str,
        header: &[String],
        rows: impl IntoIterator<Item = R>,
    ) -> miette::Result<()>
    where
        R: IntoIterator<Item = C>,
        C: AsRef<[u8]>,
    {
        let path = self.tmp.join(name);
        let write = || -> Result<(), csv::Error> {
            let mut w = csv::Writer::from_path(&path)?;
            w.write_record(header)?;
            for row in rows {
                w.write_record(row)?;
            }
            w.flush()?;
            Ok(())
        };
        write().map_err(|e| Diag::new(format!("cannot write `{}`: {e}", path.display())))?;
        self.files.push(name.to_string());
        Ok(())
    }

    /// Writes `table` as `<name>.csv`: its column names as the header, numbers in full
    /// precision, a missing value as an empty cell.
    pub fn table(&mut self, table: &Table) -> miette::Result<()> {
        let header: Vec<String> = table.columns().iter().map(|c| c.name.clone()).collect();
        let rows = (0..table.rows()).map(|r| {
            (0..header.len()).map(move |c| match table.cell(r, c) {
                Cell::Number(x) => num(x),
                Cell::Text(t) => t.to_string(),
                Cell::Missing => String::new(),
            })
        });
        self.csv(&format!("{}.csv", table.name()), &header, rows)
    }

    /// Writes the table called `name` of `tables` (see [`Output::table`]).
    pub fn table_named(&mut self, tables: &[Table], name: &str) -> miette::Result<()> {
        match tables.iter().find(|t| t.name() == name) {
            Some(t) => self.table(t),
            None => Err(Diag::new(format!("the result has no table `{name}`")).into()),
        }
    }

    /// Writes `name` (e.g. `model.toml`) with the text `content`.
    pub fn text(&mut self, name: &str, content: &str) -> miette::Result<()> {
        let path = self.tmp.join(name);
        fs::write(&path, content).map_err(|e| io_error("write", &path, e))?;
        self.files.push(name.to_string());
        Ok(())
    }

    /// Writes `name` (e.g. `time_history.npy`) as a 2-D float64 array whose columns are
    /// `columns` (all of one length): rows are samples (see the module doc for the format).
    pub fn npy(&mut self, name: &str, columns: &[&[f64]]) -> miette::Result<()> {
        let rows = columns.first().map_or(0, |c| c.len());
        if columns.iter().any(|c| c.len() != rows) {
            return Err(
                Diag::new(format!("cannot write `{name}`: columns differ in length")).into(),
            );
        }
        let path = self.tmp.join(name);
        let write = || -> std::io::Result<()> {
            let mut w = BufWriter::new(fs::File::create(&path)?);
            w.write_all(&npy_header(rows, columns.len()))?;
            for r in 0..rows {
                for c in columns {
                    w.write_all(&c[r].to_le_bytes())?;
                }
            }
            w.flush()
        };
        write().map_err(|e| io_error("write", &path, e))?;
        self.files.push(name.to_string());
        Ok(())
    }

    /// Draws an analysis's figures (`whirl_figures`), each as `<name>.png` and `.svg`, its
    /// speeds in rpm when `rpm`.
    pub fn figures(&mut self, figures: Vec<NamedFigure>, rpm: bool) -> miette::Result<()> {
        for figure in figures {
            let figure = if rpm { figure.in_rpm() } else { figure };
            self.plot(&figure.name, |stem| figure.figure.save(stem))?;
        }
        Ok(())
    }

    /// Draws a figure as `stem.png` and `stem.svg`; `draw` receives the path stem.
    pub fn plot(
        &mut self,
        stem: &str,
        draw: impl FnOnce(&Path) -> Result<Vec<PathBuf>, whirl_plot::PlotError>,
    ) -> miette::Result<()> {
        let written = draw(&self.tmp.join(stem))
            .map_err(|e| Diag::new(format!("cannot draw the plot `{stem}`: {e}")))?;
        for path in written {
            if let Some(name) = path.file_name().and_then(|n| n.to_str()) {
                self.files.push(name.to_string());
            }
        }
        Ok(())
    }

    /// Writes `summary.json` (adding the list of files) and moves the folder into place.
    /// Returns the folder and the number of files in it.
    pub fn finish(mut self, summary: &mut Value) -> miette::Result<(PathBuf, usize)> {
        self.files.push("summary.json".into());
        if let Value::Object(map) = summary {
            map.insert(
                "output_folder".into(),
                self.dir.display().to_string().into(),
            );
            map.insert("files".into(), self.files.clone().into());
        }
        let path = self.tmp.join("summary.json");
        let text = serde_json::to_string_pretty(summary)
            .map_err(|e| Diag::new(format!("cannot encode the summary: {e}")))?;
        fs::write(&path, text + "\n").map_err(|e| io_error("write", &path, e))?;
        self.replace()?;
        interrupt::forget(&self.tmp);
        self.finished = true;
        Ok((self.dir.clone(), self.files.len()))
    }

    /// Renames the temporary folder onto the final one, moving an old result aside first.
    fn replace(&self) -> miette::Result<()> {
        let old = self.tmp.with_file_name(
            self.tmp
                .file_name()
                .and_then(|n| n.to_str())
                .unwrap_or(".whirl-tmp")
                .replace(".whirl-tmp-", ".whirl-old-"),
        );
        let had_old = self.dir.exists();
        if had_old {
            if old.exists() {
                fs::remove_dir_all(&old).map_err(|e| io_error("remove", &old, e))?;
            }
            fs::rename(&self.dir, &old).map_err(|e| io_error("move aside", &self.dir, e))?;
        }
        if let Err(e) = fs::rename(&self.tmp, &self.dir) {
            if had_old {
                // Put the earlier result back.
                let _ = fs::rename(&old, &self.dir);
            }
            return Err(io_error("create", &self.dir, e).into());
        }
        if had_old {
            let _ = fs::remove_dir_all(&old);
        }
        Ok(())
    }
}

impl Drop for Output {
    fn drop(&mut self) {
        if !self.finished {
            let _ = fs::remove_dir_all(&self.tmp);
            interrupt::forget(&self.tmp);
        }
    }
}

/// The preamble of a version 1.0 `.npy` file of a C-ordered `rows` x `cols` float64 array.
fn npy_header(rows: usize, cols: usize) -> Vec<u8> {
    const MAGIC: &[u8] = b"\x93NUMPY\x01\x00";
    let dict = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': ({rows}, {cols}), }}");
    // Magic and version (8 bytes), the length (2), the dict, spaces, and a closing newline
    // make a multiple of 64 bytes, so the data is aligned for memory mapping.
    let unpadded = MAGIC.len() + 2 + dict.len() + 1;
    let padding = unpadded.next_multiple_of(64) - unpadded;
    let text = format!("{dict}{}\n", " ".repeat(padding));
    let mut header = MAGIC.to_vec();
    // The dict of a 2-D shape is well below u16::MAX bytes.
    header.extend_from_slice(&(text.len() as u16).to_le_bytes());
    header.extend_from_slice(text.as_bytes());
    header
}

/// An existing `--out` may be replaced only when it is an empty folder or an earlier result.
fn check_replaceable(dir: &Path) -> miette::Result<()> {
    let refuse = |why: &str| -> miette::Report {
        Diag::option("--out", format!("`{}` {why}", dir.display()))
            .help(
                "give a new folder, or an earlier whirl output folder (it is replaced as a whole)",
            )
            .into()
    };
    if !dir.is_dir() {
        return Err(refuse("exists and is not a folder"));
    }
    let mut entries = fs::read_dir(dir).map_err(|e| io_error("read", dir, e))?;
    let empty = entries.next().is_none();
    if empty || dir.join("summary.json").is_file() {
        Ok(())
    } else {
        Err(refuse(
            "exists and is not a whirl output folder (it has no summary.json)",
        ))
    }
}

/// A number for a CSV cell: full precision, empty when it does not exist (NaN, infinite).
pub fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x}")
    } else {
        String::new()
    }
}

/// A list of header names from string slices.
pub fn header(names: &[&str]) -> Vec<String> {
    names.iter().map(|s| s.to_string()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn npy_header_is_aligned_and_readable() {
        for (rows, cols) in [(0, 1), (3, 7), (123_456_789, 25)] {
            let h = npy_header(rows, cols);
            // NumPy's rule for version 1.0: the data starts on a multiple of 64 bytes.
            assert_eq!(h.len() % 64, 0);
            assert_eq!(&h[..8], b"\x93NUMPY\x01\x00");
            let len = u16::from_le_bytes([h[8], h[9]]) as usize;
            assert_eq!(10 + len, h.len());
            let text = std::str::from_utf8(&h[10..]).unwrap();
            assert!(text.ends_with('\n'));
            assert!(
                text.contains(&format!("'shape': ({rows}, {cols})")),
                "{text}"
            );
        }
    }
}
