//! Papier: a sheet of paper as an instrument.
pub mod render;
