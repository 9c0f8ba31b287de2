//! # Tearing: the procedural two-hand tear's building blocks
//!
//! The seeds' procedural tearing (MIG 2015 §3–4, `../shared/seeds/003_8cfb4a33a3603fcd.txt`
//! M:85–138; thesis §3.2, `../shared/seeds/000_cb4d91e46ec5927f.txt` T:1310–1419;
//! digest-tearing §1): two hands twist the sheet apart about a crack tip; each step the tip moves
//! by eq. 3.1 ([`tip`]), and the torn edge between the old and the new tip follows a
//! directed-noise walk over a fibre texture, eq. 3.2 ([`walk`], [`fibres`]). Everything here
//! lives in pattern space (metres, the sheet's rest plane), where the torn edge is a polyline the
//! mesh is cut along ([`crate::sheet::cut`]) and then opened into two lips
//! ([`crate::sheet::unzip`]), one tip step at a time ([`crate::sheet::tear_step`]).
//!
//! The sim drives them from its tear frame (`sim/tear.rs`): the tip, the cut and unzip of the
//! mesh in announced steps, and the lips' millimetre detail ([`lips`]) drawn over the straight
//! cuts.
//!
//! Decisions, one line each (digest-tearing §1.5–1.6, §1.9; none of these values is in the
//! seeds):
//! - Pattern space for the tip and the walk: the planar regions are rigid, and the texture and
//!   the cut live on the pattern.
//! - A step whose forward component (along the bisector of the directions to the thumbs) is
//!   negative does not move the tip: a tear never closes.
//! - ν = (1 − p)(1 − R) + p·G with R the fibres' resistance: the seeds' "stress resistance"
//!   texture walked to its largest value reads as a resistance inverted (digest §1.6); one
//!   resistance texture can serve the general model's fracture energy too.
//! - The walker only steps to a neighbour strictly closer to its target (the printed rule can
//!   cycle), so it ends in at most the squared distance's number of steps.

pub mod fibres;
pub mod lips;
pub mod tip;
pub mod walk;
