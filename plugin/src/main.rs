//! The standalone Papier application (nice-plug's standalone wrapper: JACK or ALSA audio and
//! MIDI, the same editor), built with the plugin by `cargo xtask bundle papier --release`.

use nice_plug::prelude::*;
use papier::Papier;

fn main() {
    nice_export_standalone::<Papier>();
}
