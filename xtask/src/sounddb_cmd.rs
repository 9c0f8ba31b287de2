//! `cargo xtask sounddb`: generate or import a sound database (see the sound issue).

/// Runs the subcommand.
pub fn run(_args: &[String]) -> anyhow::Result<()> {
    anyhow::bail!("`cargo xtask sounddb` is not available in this build yet")
}
