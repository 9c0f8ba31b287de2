//! `papier-render`: Papier's offline renderer. See `papier::offline` and the README.

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    std::process::exit(papier::offline::main_with_args(&args));
}
