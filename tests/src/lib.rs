//! Cross-crate and real-host tests for Papier: helpers shared by the test files in `tests/`.
//!
//! - [`clap`]: a small CLAP host on `clack-host` that loads the bundled `Papier.clap`;
//! - [`paths`]: where the bundles and binaries are;
//! - [`audio`]: WAV reading and signal checks.

pub mod audio;
pub mod clap;
pub mod paths;
