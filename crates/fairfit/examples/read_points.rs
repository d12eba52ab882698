//! Reads a point file (or, with `cloud`, a section or XYZ cloud file) and prints how many points it
//! holds: measures the streaming readers alone, e.g.
//! `/usr/bin/time -v target/release/examples/read_points FILE [cloud]` (see docs/reliability.md).

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: read_points FILE [cloud]");
        std::process::exit(2)
    };
    let n = if args.get(2).map(String::as_str) == Some("cloud") {
        fairfit::io::sections::read_section_file(path).map(|p| p.len())
    } else {
        fairfit::io::read_points(path).map(|p| p.points.len())
    };
    match n {
        Ok(n) => println!("{n} points"),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1)
        }
    }
}
