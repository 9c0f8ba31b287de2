//! Cross-crate and real-host tests for Papier.
