//! The checkpoint of a cascade: a folder holding `manifest.json` (what is being computed)
//! and one `point-<index>.json` per finished speed.
//!
//! Each point is written to a temporary file in the folder and renamed onto its name, so a
//! run killed at any moment leaves every point file complete or absent, never half
//! written. Numbers are JSON in the shortest form that reads back to the same f64, so a
//! resumed cascade is bit for bit the uninterrupted one. The manifest holds a hash of the
//! validated model (so editing a comment in the file keeps the checkpoint, changing a
//! number does not), the options and the derived step and band, and whirl's build
//! ([`crate::BUILD_ID`]: the version and a hash of the library's source); a
//! folder whose manifest differs is refused, never mixed. One run at a time per folder:
//! the open checkpoint holds the folder's lock (`.lock`, see [`crate::lock`]), so a second
//! run is refused, and temporary files are cleaned only by the run that holds it.
//! The writes guard against an interrupted process, not a power cut (no fsync).

use std::fs;
use std::path::{Path, PathBuf};

use serde_json::{json, Value};

use super::options::{CascadeOptions, Resolved};
use super::point::{CascadePoint, SpectrumLengths};
use crate::error::{io, Error, InputError, Result};
use crate::lock::RunLock;
use crate::model::Model;

/// Format of the folder; a change makes older folders be refused.
const FORMAT: u32 = 4;

const MANIFEST: &str = "manifest.json";

/// The lock file of a checkpoint folder, inside it.
pub(crate) const LOCK: &str = ".lock";

/// An open checkpoint folder whose manifest matches the cascade being computed; its lock
/// is held until it is dropped.
pub(super) struct Checkpoint {
    dir: PathBuf,
    /// Spectrum lengths a point of this cascade has (bins of the band, of the full band).
    lengths: SpectrumLengths,
    _lock: RunLock,
}

/// Deletes what the checkpoint folder `dir` holds, so that the cascade starts over: under
/// the folder's lock, so that a run still writing there is refused, not cut off (deleting
/// first would pull the folder from under it).
///
/// # Errors
/// [`Error::Input`] (without a field) when another run is using the folder; [`Error::Io`]
/// when it cannot be emptied.
pub fn restart(dir: &Path) -> Result<()> {
    if !dir.exists() {
        return Ok(());
    }
    let _lock = RunLock::acquire(&dir.join(LOCK), dir)?;
    for entry in fs::read_dir(dir).map_err(io("read", dir))?.flatten() {
        if entry.file_name() == LOCK {
            continue;
        }
        let path = entry.path();
        let removed = if path.is_dir() {
            fs::remove_dir_all(&path)
        } else {
            fs::remove_file(&path)
        };
        removed.map_err(io("delete", &path))?;
    }
    Ok(())
}

/// The manifest of a cascade of `model` with these options.
fn manifest(model: &Model, options: &CascadeOptions, resolved: &Resolved) -> Result<Value> {
    let model_json = serde_json::to_string(model).map_err(|source| Error::Encode {
        what: "the model for its hash".into(),
        source,
    })?;
    Ok(json!({
        "format": FORMAT,
        "whirl_version": crate::BUILD_ID,
        "model_hash": format!("{:016x}", fnv1a(model_json.as_bytes())),
        "options": options,
        "resolved": resolved,
    }))
}

/// The name of the checkpoint folder of a cascade of `model` with `options`: 16 hex digits
/// of the hash of its manifest. A tool that keeps one folder per cascade under one parent
/// (the command line's `<out>.partial/<key>`) never has one cascade's checkpoint refuse
/// another's run. To run the cascade too, [`super::PreparedCascade::checkpoint_key`] spares
/// building the model's system twice.
///
/// # Errors
/// [`Error::Input`] for bad options, as [`super::cascade`].
pub fn key(model: &Model, options: &CascadeOptions) -> Result<String> {
    super::PreparedCascade::new(model, options)?.checkpoint_key()
}

/// The key of the cascade of `model` with `options`, whose shared numbers are `resolved`.
pub(super) fn key_of(
    model: &Model,
    options: &CascadeOptions,
    resolved: &Resolved,
) -> Result<String> {
    let manifest = manifest(model, options, resolved)?;
    Ok(format!("{:016x}", fnv1a(manifest.to_string().as_bytes())))
}

/// FNV-1a, 64 bits: a hash that stays the same across Rust versions and platforms.
pub(crate) fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

impl Checkpoint {
    /// Opens (creating if needed) the checkpoint folder `dir` for this cascade.
    ///
    /// # Errors
    /// [`Error::Input`] (field `checkpoint`) when the folder holds another cascade: other
    /// model, options or whirl version; (without a field) when another run is using it;
    /// [`Error::Io`] when it cannot be read or written.
    pub(super) fn open(
        dir: &Path,
        model: &Model,
        options: &CascadeOptions,
        resolved: &Resolved,
    ) -> Result<Checkpoint> {
        let wanted = manifest(model, options, resolved)?;
        fs::create_dir_all(dir).map_err(io("create the checkpoint folder", dir))?;
        // Before anything in the folder is read or cleaned: a live run's files are its own.
        let lock = RunLock::acquire(&dir.join(LOCK), dir)?;
        let path = dir.join(MANIFEST);
        if path.exists() {
            let text = fs::read_to_string(&path).map_err(io("read", &path))?;
            let found: Value = serde_json::from_str(&text).unwrap_or(Value::Null);
            if found != wanted {
                return Err(mismatch(dir, &found, &wanted));
            }
        } else {
            let text = serde_json::to_string_pretty(&wanted).map_err(|source| Error::Encode {
                what: "the manifest".into(),
                source,
            })?;
            write_atomically(&path, text.as_bytes())?;
        }
        remove_leftovers(dir)?;
        Ok(Checkpoint {
            dir: dir.to_path_buf(),
            lengths: SpectrumLengths::of(options, resolved),
            _lock: lock,
        })
    }

    fn point_path(&self, index: usize) -> PathBuf {
        self.dir.join(format!("point-{index:05}.json"))
    }

    /// The finished point `index` at `speed` (rad/s), if it was saved. A file that cannot
    /// be read, holds another speed, or holds what no run writes (a spectrum of another
    /// length, a negative or non-finite amplitude: a damaged or edited file) counts as not
    /// saved: it is computed again, never trusted.
    pub(super) fn load(&self, index: usize, speed: f64) -> Option<CascadePoint> {
        let text = fs::read_to_string(self.point_path(index)).ok()?;
        let point: CascadePoint = serde_json::from_str(&text).ok()?;
        (point.speed == speed && point.is_whole(self.lengths)).then_some(point)
    }

    /// Saves point `index` atomically.
    pub(super) fn save(&self, index: usize, point: &CascadePoint) -> Result<()> {
        let text = serde_json::to_string(point).map_err(|source| Error::Encode {
            what: "a cascade point".into(),
            source,
        })?;
        write_atomically(&self.point_path(index), text.as_bytes())
    }

    /// The folder.
    pub(super) fn dir(&self) -> &Path {
        &self.dir
    }
}

/// Writes `bytes` to a temporary file beside `path` and renames it onto `path`.
pub(crate) fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    let name = path
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or("checkpoint");
    let tmp = path.with_file_name(format!(".{name}.tmp-{}", std::process::id()));
    fs::write(&tmp, bytes).map_err(io("write", &tmp))?;
    fs::rename(&tmp, path).map_err(io("rename into place", path))
}

/// Removes temporary files a killed run left behind (called with the folder's lock held,
/// so none of them belongs to a live run).
fn remove_leftovers(dir: &Path) -> Result<()> {
    for entry in fs::read_dir(dir).map_err(io("read", dir))?.flatten() {
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if name.starts_with('.') && name.contains(".tmp-") {
            let _ = fs::remove_file(entry.path());
        }
    }
    Ok(())
}

/// The refusal to mix two cascades, naming what differs.
fn mismatch(dir: &Path, found: &Value, wanted: &Value) -> Error {
    let differs = |key: &str| found.get(key) != wanted.get(key);
    let mut what: Vec<String> = Vec::new();
    if differs("model_hash") {
        what.push("the model".into());
    }
    for group in ["options", "resolved"] {
        if let (Some(Value::Object(a)), Some(Value::Object(b))) =
            (found.get(group), wanted.get(group))
        {
            what.extend(b.keys().filter(|k| a.get(*k) != b.get(*k)).cloned());
        }
    }
    if differs("format") || differs("whirl_version") || what.is_empty() {
        what.push("the whirl build (its version or source) or checkpoint format".into());
    }
    InputError::field(
        "checkpoint",
        format!(
            "the checkpoint folder `{}` holds a cascade that differs in {}; its finished \
             speeds cannot be mixed with this run's",
            dir.display(),
            what.join(", ")
        ),
    )
    .help(
        "delete that folder to start over (whirl cascade: --restart), or write this run \
         elsewhere",
    )
    .into()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A checkpoint in `dir` for points with 3 band bins and no full spectrum.
    fn checkpoint(dir: &Path) -> Checkpoint {
        Checkpoint {
            dir: dir.to_path_buf(),
            lengths: SpectrumLengths::for_test(3, 0),
            _lock: RunLock::acquire(&dir.join(LOCK), dir).unwrap(),
        }
    }

    fn point() -> CascadePoint {
        let mut p = CascadePoint::settled_at(100.0, 1e-5, None);
        p.amplitude = vec![1e-6, 2e-6, 0.0];
        p
    }

    #[test]
    fn a_tampered_point_is_computed_again_not_trusted() {
        let dir = tempfile::tempdir().unwrap();
        let c = checkpoint(dir.path());
        let p = point();
        c.save(0, &p).unwrap();
        assert_eq!(c.load(0, p.speed), Some(p.clone()));
        // A negative 1X went into nsv.csv; a truncated spectrum failed in the plots.
        let text = fs::read_to_string(c.point_path(0)).unwrap();
        let tampered = [
            text.replace("\"one_x_m\":0.00001", "\"one_x_m\":-5.0"),
            text.replace("[1e-6,2e-6,0.0]", "[1e-6,2e-6]"),
            text.replace("[1e-6,2e-6,0.0]", "[1e-6,-2e-6,0.0]"),
        ];
        for bad in tampered {
            assert_ne!(bad, text, "the edit must apply");
            fs::write(c.point_path(0), &bad).unwrap();
            assert_eq!(c.load(0, p.speed), None, "{bad}");
        }
    }

    #[test]
    fn a_restart_while_another_run_holds_the_folder_is_refused_and_deletes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let c = checkpoint(dir.path());
        c.save(0, &point()).unwrap();
        let e = restart(dir.path()).unwrap_err().to_string();
        assert!(e.contains("another whirl run"), "{e}");
        assert!(c.point_path(0).exists());
        drop(c);
        restart(dir.path()).unwrap();
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    #[test]
    fn fnv1a_matches_its_published_vectors() {
        // Reference values of the FNV-1a 64-bit test suite (Fowler, Noll, Vo).
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a(b"foobar"), 0x8594_4171_f739_67e8);
    }
}
