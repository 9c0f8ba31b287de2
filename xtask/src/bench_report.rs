//! `cargo xtask bench-report`: benchmark report (see the sim-core issue).

/// Runs the subcommand.
pub fn run(_args: &[String]) -> anyhow::Result<()> {
    anyhow::bail!("`cargo xtask bench-report` is not available in this build yet")
}
