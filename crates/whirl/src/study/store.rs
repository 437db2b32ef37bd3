//! The checkpoint folder of a study: each finished point saved at once, so an interrupted
//! study continues where it stopped.
//!
//! Layout: `study.json` records the fingerprint of the study that started the folder (its
//! sweeps and its points' inputs); `points/<key>.json` holds one finished point, `<key>`
//! being the fingerprint of that point's exact input (validated model after its edits,
//! cascade settings, whirl build: version and source hash). A point file is written to a temporary name and renamed into place, so
//! it is either whole or absent, whatever the moment of interruption. A folder started by a
//! different study file or model is refused rather than mixed; a point file that cannot be
//! read back (written by another whirl version) is computed again. The open store holds
//! the folder's lock (`.lock`, see [`crate::lock`]): one study at a time per folder.

use std::fs;
use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use crate::error::{io, Error, InputError, Result};
use crate::lock::RunLock;
use crate::nsv::checkpoint::{fnv1a, write_atomically, LOCK};

/// The manifest of a checkpoint folder.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct Manifest {
    /// Fingerprint of the study.
    fingerprint: String,
    /// The study file, for the message when it does not match.
    study_file: String,
}

/// An open checkpoint folder; its lock is held until it is dropped.
#[derive(Debug)]
pub struct Store {
    dir: PathBuf,
    _lock: RunLock,
}

/// FNV-1a, 64 bits, of `parts` separated by a zero byte, as 16 hex digits: a fingerprint
/// stable across runs, machines and Rust versions (std's hasher promises none of that).
pub fn fingerprint(parts: &[&str]) -> String {
    let bytes: Vec<u8> = parts
        .iter()
        .flat_map(|p| p.bytes().chain(std::iter::once(0)))
        .collect();
    format!("{:016x}", fnv1a(&bytes))
}

impl Store {
    /// Opens (or creates) the checkpoint folder `dir` for the study whose fingerprint is
    /// `fingerprint`. With `restart`, points of an earlier study are discarded; without it,
    /// a folder of a different study is an error that says what to do, and a folder that
    /// another run is using is refused.
    ///
    /// # Errors
    /// [`Error::Io`] when the folder cannot be created or written, [`Error::Input`] when it
    /// holds another study's points (without `restart`), [`Error::Encode`] when the manifest
    /// cannot be encoded.
    pub fn open(dir: &Path, fingerprint: &str, study_file: &Path, restart: bool) -> Result<Store> {
        fs::create_dir_all(dir).map_err(io("create the folder", dir))?;
        let manifest_path = dir.join("study.json");
        let store = Store {
            dir: dir.to_path_buf(),
            _lock: RunLock::acquire(&dir.join(LOCK), dir)?,
        };
        if restart && dir.join("points").is_dir() {
            fs::remove_dir_all(dir.join("points")).map_err(io("remove", dir))?;
        } else if let Some(old) = read_manifest(&manifest_path) {
            if old.fingerprint != fingerprint {
                return Err(different_study(dir, &old, store.finished()).into());
            }
        } else if store.finished() > 0 {
            return Err(different_study(dir, &unknown_manifest(), store.finished()).into());
        }
        fs::create_dir_all(dir.join("points")).map_err(io("create the folder", dir))?;
        let manifest = Manifest {
            fingerprint: fingerprint.to_string(),
            study_file: study_file.display().to_string(),
        };
        let text = serde_json::to_string_pretty(&manifest).map_err(|source| Error::Encode {
            what: "the study manifest".into(),
            source,
        })?;
        write_atomically(&manifest_path, text.as_bytes())?;
        Ok(store)
    }

    /// The folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Number of finished points in the folder.
    pub fn finished(&self) -> usize {
        fs::read_dir(self.dir.join("points")).map_or(0, |entries| {
            entries
                .filter_map(|e| e.ok())
                .filter(|e| e.path().extension().is_some_and(|x| x == "json"))
                .count()
        })
    }

    /// The finished point `key`, when it is there and readable.
    pub fn load<T: DeserializeOwned>(&self, key: &str) -> Option<T> {
        let text = fs::read_to_string(self.point_path(key)).ok()?;
        serde_json::from_str(&text).ok()
    }

    /// Saves the finished point `key` atomically.
    ///
    /// # Errors
    /// [`Error::Encode`] when the point cannot be encoded, [`Error::Io`] when it cannot be
    /// written.
    pub fn save<T: Serialize>(&self, key: &str, point: &T) -> Result<()> {
        let text = serde_json::to_string(point).map_err(|source| Error::Encode {
            what: format!("point {key}"),
            source,
        })?;
        write_atomically(&self.point_path(key), text.as_bytes())
    }

    fn point_path(&self, key: &str) -> PathBuf {
        self.dir.join("points").join(format!("{key}.json"))
    }
}

/// The folder under a study's checkpoint folder holding the cascades still running
/// ([`super::Point::partial_dir`]).
pub const PARTIAL: &str = "partial";

/// Removes the running cascades' folder of the study checkpoint `store_dir`: called once
/// every point is saved, when no point can resume them any more. A folder that cannot be
/// removed is left (it only holds finished speeds).
pub fn remove_partial(store_dir: &Path) {
    let _ = fs::remove_dir_all(store_dir.join(PARTIAL));
}

fn read_manifest(path: &Path) -> Option<Manifest> {
    serde_json::from_str(&fs::read_to_string(path).ok()?).ok()
}

fn unknown_manifest() -> Manifest {
    Manifest {
        fingerprint: String::new(),
        study_file: "an unknown study (its study.json is missing or unreadable)".into(),
    }
}

fn different_study(dir: &Path, old: &Manifest, finished: usize) -> InputError {
    InputError::field(
        "--checkpoint",
        format!(
            "`{}` holds {finished} finished points of a different study ({}, or its model, \
             has changed since they were computed); whirl does not mix them",
            dir.display(),
            old.study_file
        ),
    )
    .help(
        "give --restart to discard those points and start again, or --checkpoint with \
         another folder to keep them",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("whirl-store-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        dir
    }

    #[test]
    fn fingerprint_is_fnv1a() {
        // FNV-1a 64 of the empty string is the offset basis; of "a\0" two rounds.
        assert_eq!(fingerprint(&[]), "cbf29ce484222325");
        assert_ne!(fingerprint(&["ab", "c"]), fingerprint(&["a", "bc"]));
    }

    #[test]
    fn saves_loads_and_refuses_a_different_study() {
        let dir = temp_dir("refuse");
        let study = Path::new("study.toml");
        let store = Store::open(&dir, "one", study, false).unwrap();
        store.save("k1", &vec![1.5, 2.5]).unwrap();
        assert_eq!(store.load::<Vec<f64>>("k1"), Some(vec![1.5, 2.5]));
        assert_eq!(store.load::<Vec<f64>>("k2"), None);
        // Reopened by the same study: the point is still there.
        drop(store);
        let again = Store::open(&dir, "one", study, false).unwrap();
        assert_eq!(again.finished(), 1);
        // While it is open, a second run on the folder is refused.
        let busy = Store::open(&dir, "one", study, false)
            .unwrap_err()
            .to_string();
        assert!(busy.contains("is writing"), "{busy}");
        drop(again);
        // A different study is refused, naming the fix.
        let e = Store::open(&dir, "two", study, false)
            .unwrap_err()
            .to_string();
        assert!(e.contains("1 finished points of a different study"), "{e}");
        assert!(e.contains("--restart"), "{e}");
        // --restart discards the old points.
        let fresh = Store::open(&dir, "two", study, true).unwrap();
        assert_eq!(fresh.finished(), 0);
        let _ = fs::remove_dir_all(&dir);
    }
}
