//! The subcommands' command lines: positional arguments parsed strictly (a bad one is a
//! [`BadArgs`] error, which `main` prints with the usage, exit status 2), and the options read
//! from environment variables (an unset or unparsable variable leaves the default).

use std::str::FromStr;

/// A bad command line (one line, without the usage, which `main` adds).
#[derive(Debug)]
pub struct BadArgs(pub String);

impl std::fmt::Display for BadArgs {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for BadArgs {}

/// A [`BadArgs`] error.
pub fn bad(msg: impl Into<String>) -> anyhow::Error {
    anyhow::Error::new(BadArgs(msg.into()))
}

/// Refuses more than `n` arguments.
pub fn at_most(args: &[String], n: usize) -> anyhow::Result<()> {
    match args.get(n) {
        Some(a) => Err(bad(format!("unexpected argument {a:?}"))),
        None => Ok(()),
    }
}

/// `s` parsed as the argument `what`.
pub fn parse<T: FromStr>(s: &str, what: &str) -> anyhow::Result<T> {
    s.parse().map_err(|_| bad(format!("bad {what}: {s:?}")))
}

/// The positional argument `i` parsed as `what`, or `None` when there is none.
pub fn nth<T: FromStr>(args: &[String], i: usize, what: &str) -> anyhow::Result<Option<T>> {
    args.get(i).map(|s| parse(s, what)).transpose()
}

/// True if the environment variable `name` is set to `value`.
pub fn env_is(name: &str, value: &str) -> bool {
    std::env::var(name).is_ok_and(|v| v == value)
}

/// The environment variable `name` parsed, or `None` when unset or unparsable.
pub fn env_num<T: FromStr>(name: &str) -> Option<T> {
    std::env::var(name).ok().and_then(|v| v.parse().ok())
}
