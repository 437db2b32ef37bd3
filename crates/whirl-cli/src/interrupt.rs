//! Ctrl-C (SIGINT, and SIGTERM): stop cleanly.
//!
//! Commands whose long work can stop between pieces (a cascade between speeds, a study
//! between points) call [`stoppable`] and ask [`requested`] as they go: the first Ctrl-C
//! lets the pieces running finish, keeps every finished one in the checkpoint folder and
//! ends with exit status 130. Any other command, or a second Ctrl-C, quits at once: the
//! temporary output folders and lock files registered here are removed first, so an
//! interrupted run leaves nothing behind but its checkpoint.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

/// Exit status of a run stopped by Ctrl-C (128 + SIGINT, as shells report it).
pub const EXIT_INTERRUPTED: u8 = 130;

static REQUESTED: AtomicBool = AtomicBool::new(false);
static STOPPABLE: AtomicBool = AtomicBool::new(false);
static LEFTOVERS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Installs the handler. A failure to install leaves the default (the process dies, and
/// the next run cleans up what it left), so it is not an error.
pub fn install() {
    let _ = ctrlc::set_handler(on_signal);
}

/// True once Ctrl-C was pressed.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}

/// Says that this run asks [`requested`] between pieces of work, so the first Ctrl-C
/// waits for it to stop.
pub fn stoppable() {
    STOPPABLE.store(true, Ordering::Relaxed);
}

/// Registers a temporary folder or file to remove if the process quits at once.
pub fn remove_on_quit(path: &Path) {
    if let Ok(mut list) = LEFTOVERS.lock() {
        list.push(path.to_path_buf());
    }
}

/// Forgets a path registered with [`remove_on_quit`] (it was moved into place or removed).
pub fn forget(path: &Path) {
    if let Ok(mut list) = LEFTOVERS.lock() {
        list.retain(|p| p != path);
    }
}

fn on_signal() {
    let again = REQUESTED.swap(true, Ordering::Relaxed);
    if again || !STOPPABLE.load(Ordering::Relaxed) {
        quit();
    }
    let _ = writeln!(
        std::io::stderr(),
        "\nstopping: the work running now finishes and everything finished is kept \
         (Ctrl-C again to quit at once)"
    );
}

/// Removes the registered leftovers and exits with [`EXIT_INTERRUPTED`].
fn quit() -> ! {
    if let Ok(list) = LEFTOVERS.lock() {
        for path in list.iter() {
            let _ = if path.is_dir() {
                std::fs::remove_dir_all(path)
            } else {
                std::fs::remove_file(path)
            };
        }
    }
    let _ = writeln!(std::io::stderr(), "\ninterrupted");
    std::process::exit(i32::from(EXIT_INTERRUPTED))
}
