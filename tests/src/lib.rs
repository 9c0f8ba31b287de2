//! Cross-crate and real-host tests for Papier: helpers shared by the test files in `tests/`.
//!
//! - [`clap`]: a small CLAP host on `clack-host` that loads the bundled `Papier.clap`;
//! - [`clap_gui`]: the host's side of showing the plugin's editor (CLAP GUI extension, X11);
//! - [`paths`]: where the bundles and binaries are;
//! - [`audio`]: WAV reading and signal checks;
//! - [`live`]: a host audio thread at real-time pace, for tests that run audio alongside;
//! - [`xvfb`]: a private virtual X server and the X tools the GUI tests use;
//! - [`screenshot`]: window screenshots as RGB images;
//! - [`small_db`]: the small user sound database the tests cut from a full one.

pub mod audio;
pub mod clap;
pub mod clap_gui;
pub mod live;
pub mod paths;
pub mod screenshot;
pub mod small_db;
pub mod xvfb;
