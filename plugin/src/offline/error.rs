//! # Why an offline render failed ([`OfflineError`]: one line each, with its exit code).

use thiserror::Error;

/// Why a render failed. Every message is one line.
#[derive(Debug, Error)]
pub enum OfflineError {
    /// Bad command line.
    #[error("{0}")]
    Usage(String),
    /// An input cannot be used.
    #[error("{0}")]
    Input(String),
    /// Output cannot be written.
    #[error("{0}")]
    Output(String),
    /// The engine could not start.
    #[error("{0}")]
    Engine(String),
}

impl OfflineError {
    /// Process exit code: 2 for usage errors, 1 otherwise.
    pub fn exit_code(&self) -> i32 {
        match self {
            OfflineError::Usage(_) => 2,
            _ => 1,
        }
    }
}
