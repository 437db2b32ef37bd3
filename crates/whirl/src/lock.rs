//! One run at a time per folder: a lock file that a crashed run does not leave locked.
//!
//! The lock is the operating system's advisory lock on a file (`flock` on Unix,
//! `LockFileEx` on Windows), taken without waiting. The system releases it when the holder
//! exits in any way, a `kill -9` or a crash included, so a lock left by a dead run is
//! simply taken over by the next one: no process ids to compare, no stale locks to break
//! by hand. The file holds the holder's process id, for the message a second run gets.
//! It is removed when the holder lets go; a file left by a killed run is reused (and then
//! removed) by the next run.
//!
//! Removing a lock file while another process waits to open it is a known race: that
//! process could lock the removed file while a third creates a new one. So after locking,
//! the holder checks that its open file is still the one at the path, and tries again if
//! not.

use std::fs::{self, File, OpenOptions, TryLockError};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};

use crate::error::{io, Error, InputError, Result};

/// Attempts at taking a lock whose file was replaced meanwhile (see the module doc); two
/// replacements in a row need three runs racing for one folder, so three is plenty.
const ATTEMPTS: usize = 3;

/// A held lock; released (and its file removed) when dropped.
#[derive(Debug)]
pub struct RunLock {
    path: PathBuf,
    file: File,
}

impl RunLock {
    /// Takes the lock file `path` for a run that writes `what` (a folder, named in the
    /// message of a run that is refused). Does not wait.
    ///
    /// # Errors
    /// [`Error::Input`] (without a field) when another run holds it, with that run's
    /// process id; [`Error::Io`] when the file cannot be created.
    pub fn acquire(path: &Path, what: &Path) -> Result<RunLock> {
        for _ in 0..ATTEMPTS {
            let mut file = open_own(path)?;
            match file.try_lock() {
                Ok(()) => {}
                Err(TryLockError::WouldBlock) => return Err(busy(&mut file, path, what)),
                Err(TryLockError::Error(e)) => return Err(io("lock", path)(e)),
            }
            if !same_file(&file, path) {
                // Removed by its previous holder while we were opening it: start again.
                continue;
            }
            let write = |f: &mut File| -> std::io::Result<()> {
                f.set_len(0)?;
                f.rewind()?;
                writeln!(f, "{}", std::process::id())
            };
            write(&mut file).map_err(io("write", path))?;
            return Ok(RunLock {
                path: path.to_path_buf(),
                file,
            });
        }
        Err(refusal(format!(
            "the lock file `{}` kept changing while it was being taken: several runs are \
             starting on `{}` at once",
            path.display(),
            what.display()
        )))
    }

    /// The lock file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for RunLock {
    fn drop(&mut self) {
        // Removed while still locked, so no one can lock this file after we let go (the
        // race is closed by the check in `acquire`).
        let _ = fs::remove_file(&self.path);
        let _ = self.file.unlock();
    }
}

/// Opens (or creates) the lock file without following a symbolic link and refuses a file
/// that is not this user's own plain file: in a shared folder, a link or a file planted by
/// another user would otherwise make whirl write its process id into a file of their
/// choosing.
fn open_own(path: &Path) -> Result<File> {
    let mut options = OpenOptions::new();
    options.read(true).write(true).create(true).truncate(false);
    no_follow(&mut options);
    let file = options.open(path).map_err(|e| {
        if is_link(path) {
            planted(path, "is a symbolic link")
        } else {
            io("create the lock file", path)(e)
        }
    })?;
    match foreign(&file) {
        Some(why) => Err(planted(path, &why)),
        None => Ok(file),
    }
}

fn is_link(path: &Path) -> bool {
    fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink())
}

#[cfg(unix)]
fn no_follow(options: &mut OpenOptions) {
    use std::os::unix::fs::OpenOptionsExt;
    options.custom_flags(nix::fcntl::OFlag::O_NOFOLLOW.bits());
}

/// Windows does not follow a symbolic link to a file unless asked; nothing to add.
#[cfg(not(unix))]
fn no_follow(_options: &mut OpenOptions) {}

/// Why an open lock file is not one whirl may write: another user's, not a plain file, or
/// a hard link to a file elsewhere; `None` when it is fine.
#[cfg(unix)]
fn foreign(file: &File) -> Option<String> {
    use std::os::unix::fs::MetadataExt;
    let meta = match file.metadata() {
        Ok(m) => m,
        Err(e) => return Some(format!("cannot be inspected ({e})")),
    };
    if meta.uid() != nix::unistd::geteuid().as_raw() {
        Some(format!("belongs to another user (uid {})", meta.uid()))
    } else if !meta.file_type().is_file() {
        Some("is not a plain file".into())
    } else if meta.nlink() > 1 {
        Some(format!(
            "has {} hard links (a link to another file)",
            meta.nlink()
        ))
    } else {
        None
    }
}

#[cfg(not(unix))]
fn foreign(_file: &File) -> Option<String> {
    None
}

/// The refusal of a lock file that whirl did not make.
fn planted(path: &Path, why: &str) -> Error {
    let mut e = refusal(format!(
        "the lock file `{}` {why}: whirl writes its process id into it and will not write \
         into a file it did not create",
        path.display()
    ));
    if let Error::Input(input) = &mut e {
        input.help = Some(format!(
            "remove `{}` if no whirl run is using the folder, or write elsewhere (--out)",
            path.display()
        ));
    }
    e
}

/// True when `file` is the file now at `path` (not one removed and created anew).
#[cfg(unix)]
fn same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// Windows does not let a locked file be removed, so the path always holds the file.
#[cfg(not(unix))]
fn same_file(_file: &File, path: &Path) -> bool {
    path.exists()
}

/// The refusal: another run holds the lock, named by its process id when it wrote one.
fn busy(file: &mut File, path: &Path, what: &Path) -> Error {
    let mut text = String::new();
    let holder = match file.read_to_string(&mut text) {
        Ok(_) if !text.trim().is_empty() => format!("another whirl run (process {})", text.trim()),
        _ => "another whirl run".to_string(),
    };
    let mut e = refusal(format!("{holder} is writing `{}`", what.display()));
    if let Error::Input(input) = &mut e {
        input.help = Some(format!(
        "wait for it to finish, or write this run elsewhere (--out); the lock `{}` is released \
         when that process ends, even if it is killed",
            path.display()
        ));
    }
    e
}

/// An input error without a field: the folder given is in use, nothing in it is wrong.
fn refusal(message: String) -> Error {
    Error::Input(Box::new(InputError {
        file: None,
        field: None,
        message,
        help: None,
        span: None,
        line_column: None,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(unix)]
    #[test]
    fn a_lock_file_planted_as_a_link_is_refused_and_its_target_untouched() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("precious.txt");
        fs::write(&target, "keep me\n").unwrap();
        type Plant = fn(&Path, &Path) -> std::io::Result<()>;
        let plants: [(&str, Plant); 2] = [
            (".symlink.lock", |a, b| std::os::unix::fs::symlink(a, b)),
            (".hardlink.lock", |a, b| fs::hard_link(a, b)),
        ];
        for (name, plant) in plants {
            let lock = dir.path().join(name);
            plant(&target, &lock).unwrap();
            let e = RunLock::acquire(&lock, dir.path()).unwrap_err().to_string();
            assert!(
                e.contains("will not write into a file it did not create"),
                "{e}"
            );
            assert_eq!(fs::read_to_string(&target).unwrap(), "keep me\n");
        }
    }

    #[test]
    fn a_second_lock_is_refused_until_the_first_is_dropped() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(".lock");
        let first = RunLock::acquire(&path, dir.path()).unwrap();
        // flock locks conflict between two open files even within one process.
        let e = RunLock::acquire(&path, dir.path()).unwrap_err().to_string();
        assert!(
            e.contains(&format!("process {}", std::process::id())),
            "{e}"
        );
        drop(first);
        assert!(!path.exists(), "the lock file is removed on release");
        let again = RunLock::acquire(&path, dir.path()).unwrap();
        assert_eq!(again.path(), path);
    }

    #[test]
    fn a_file_left_by_a_dead_run_is_taken_over() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(".lock");
        // What a killed run leaves: the file with its pid, no lock held on it.
        fs::write(&path, "999999999\n").unwrap();
        let lock = RunLock::acquire(&path, dir.path()).unwrap();
        let text = fs::read_to_string(&path).unwrap();
        assert_eq!(text.trim(), std::process::id().to_string());
        drop(lock);
    }
}
