//! Why a scenario was refused.

/// Why a scenario was refused.
#[derive(Debug, thiserror::Error)]
pub enum ScenarioError {
    /// The file could not be read.
    #[error("{origin}: cannot read the scenario: {source}")]
    Read {
        /// File name.
        origin: String,
        /// Underlying error.
        #[source]
        source: std::io::Error,
    },
    /// Not valid TOML (or a tool path that is not valid CSV).
    #[error("{location}: {message}")]
    Syntax {
        /// `file:line` (or just the file when the position is unknown).
        location: String,
        /// What is wrong.
        message: String,
    },
    /// A key that is unknown, missing, of the wrong type, out of its range or inconsistent
    /// with another.
    #[error("{location}: `{key}` {message}")]
    Invalid {
        /// `file:line` of the key, or of its section, or just the file; `--set KEY=VALUE` for
        /// an override.
        location: String,
        /// Dotted path of the key, e.g. `target[0].normal` (0-based index).
        key: String,
        /// What is wrong.
        message: String,
    },
}
