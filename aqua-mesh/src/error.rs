//! Typed errors of the geometry crate.
//!
//! Every message names the object, the key (or file position), the offending value and what
//! would be valid (docs/theory/cages.md#input-validation).

use std::fmt;
use std::path::PathBuf;

/// Where in an input file a problem was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FilePos {
    /// 1-based line of an ASCII file.
    Line(usize),
    /// 0-based byte offset (binary files, or when no line is known).
    Byte(usize),
    /// The file as a whole.
    File,
}

impl fmt::Display for FilePos {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FilePos::Line(l) => write!(f, "line {l}"),
            FilePos::Byte(b) => write!(f, "byte offset {b}"),
            FilePos::File => f.write_str("file"),
        }
    }
}

/// Errors of the builders, the gmsh reader and the VTK writers.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// A parameter has a value outside its valid range.
    #[error("{object}: `{key}` = {value} is invalid: {valid}")]
    InvalidParameter {
        /// Object name (e.g. `cage0`).
        object: String,
        /// Parameter key as written in the scene file (e.g. `element_length`, `net.half_mesh`).
        key: String,
        /// The value given.
        value: String,
        /// What would be valid, and where useful the fix.
        valid: String,
    },
    /// A key that the chosen type does not use.
    #[error("{object}: key `{key}` is not used by type {kind}; keys of {kind}: {valid_keys}")]
    KeyNotForType {
        /// Object name.
        object: String,
        /// The offending key.
        key: String,
        /// The object type (e.g. `CCT`).
        kind: String,
        /// Comma-separated list of the keys this type accepts.
        valid_keys: String,
    },
    /// A group name that does not exist (in `fixed`, `groups.<name>`, …).
    #[error(
        "{object}: `{key}` names group `{name}`, which does not exist; groups produced: {valid}"
    )]
    UnknownGroup {
        /// Object name.
        object: String,
        /// Key that holds the name.
        key: String,
        /// The unknown group name.
        name: String,
        /// Comma-separated valid names.
        valid: String,
    },
    /// An inconsistency between several parameters (overlapping frames, weight depth, …).
    #[error("{object}: {message}")]
    Inconsistent {
        /// Object name.
        object: String,
        /// Full explanation naming the keys and values involved.
        message: String,
    },
    /// A gmsh file that cannot be read or used.
    #[error("{}: {position}: {message}", file.display())]
    Gmsh {
        /// The file.
        file: PathBuf,
        /// Line (ASCII) or byte offset (binary) of the problem.
        position: FilePos,
        /// What is wrong and what would be valid.
        message: String,
    },
    /// Arrays passed to a VTK writer that do not fit the mesh.
    #[error("VTK {location} array `{name}`: {message}")]
    VtkArray {
        /// `point` or `cell`.
        location: &'static str,
        /// Array name.
        name: String,
        /// What is wrong.
        message: String,
    },
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// Underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// A VTK output file name the writer cannot use.
    #[error("{}: {message}", path.display())]
    VtkPath {
        /// The file or directory.
        path: PathBuf,
        /// What is wrong and what would be valid.
        message: String,
    },
}

impl MeshError {
    /// Shorthand for [`MeshError::InvalidParameter`].
    pub fn param(
        object: &str,
        key: &str,
        value: impl fmt::Display,
        valid: impl Into<String>,
    ) -> Self {
        MeshError::InvalidParameter {
            object: object.to_string(),
            key: key.to_string(),
            value: value.to_string(),
            valid: valid.into(),
        }
    }

    /// Shorthand for [`MeshError::Inconsistent`].
    pub fn inconsistent(object: &str, message: impl Into<String>) -> Self {
        MeshError::Inconsistent {
            object: object.to_string(),
            message: message.into(),
        }
    }
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, MeshError>;
