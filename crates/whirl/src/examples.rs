//! The bundled example models, shared by tests, benchmarks and documentation.
//!
//! The files live in the crate's `models/` folder, so that the published crate carries
//! them; the repository's `examples/` holds copies as real files (a copied `examples/`
//! folder must not hold dangling links), which a test keeps identical.

/// The reference rotor of docs/theory.md section 9 (`examples/reference_rotor.toml`).
pub const REFERENCE_ROTOR: &str = include_str!("../models/reference_rotor.toml");

/// The reference rotor on 1e6 N/m supports (`examples/reference_rotor_soft.toml`).
pub const REFERENCE_ROTOR_SOFT: &str = include_str!("../models/reference_rotor_soft.toml");

#[cfg(test)]
mod tests {
    use std::path::Path;

    /// The repository's `examples/` folder (absent from the published crate).
    fn examples() -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
    }

    #[test]
    fn the_repository_examples_are_the_bundled_models() {
        for (name, text) in [
            ("reference_rotor.toml", super::REFERENCE_ROTOR),
            ("reference_rotor_soft.toml", super::REFERENCE_ROTOR_SOFT),
        ] {
            let copy = std::fs::read_to_string(examples().join(name)).unwrap();
            assert_eq!(copy, text, "examples/{name} differs from models/{name}");
        }
    }

    #[test]
    fn the_repository_examples_are_real_files() {
        for entry in std::fs::read_dir(examples()).unwrap() {
            let path = entry.unwrap().path();
            let kind = std::fs::symlink_metadata(&path).unwrap().file_type();
            assert!(!kind.is_symlink(), "{} is a link", path.display());
        }
    }
}
