//! A stable-toolchain fuzzing harness for every reader: points (CSV/XYZ/TXT), section and cloud files,
//! fairfit JSON, meshes (PLY ascii and binary, STL, OBJ), STEP and IGES.
//!
//! Each target starts from a seed corpus of the repository's own files (examples/data,
//! crates/fairfit/tests/data) and meshes made here, and reads deterministic mutations of them (bit and
//! byte flips, insertions of digits, separators, huge counts and non-finite numbers, deletions,
//! duplicated and truncated chunks, spliced seeds). Every input must end in `Ok` or an `Err` whose
//! message is one line: no panic, no single allocation over [`MAX_ALLOCATION`] (a counting global
//! allocator in this test binary checks it), and the slowest input is printed.
//!
//! The inputs are a pure function of the seed corpus and the iteration number, so a failure repeats.
//! `cargo test --release -p fairfit --test fuzz_readers` runs [`DEFAULT_ITERATIONS`] inputs per target;
//! `FAIRFIT_FUZZ_SECS=S` runs each target for `S` seconds instead, and `FAIRFIT_FUZZ_START=K` starts at
//! iteration K (see docs/reliability.md, "Fuzzing").

use fairfit::io::{cad_read, mesh_read, points, sections};
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// No reader may ask for a single block larger than this on inputs of at most a few MB.
const MAX_ALLOCATION: usize = 256 << 20;
/// Inputs per target in a plain `cargo test` run.
const DEFAULT_ITERATIONS: u64 = 300;
/// Largest mutated input, in bytes.
const MAX_INPUT: usize = 1 << 20;

struct Counting;
static LARGEST: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        LARGEST.fetch_max(new_size, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// SplitMix64: a small deterministic generator.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Tokens that probe the readers' edges: counts, separators, non-finite and huge numbers.
const TOKENS: &[&str] = &[
    "0",
    "-1",
    "1e308",
    "-1e308",
    "1e-320",
    "nan",
    "inf",
    "NaN",
    "99999999",
    "4294967296",
    "18446744073709551616",
    ",",
    ";",
    " ",
    "\n",
    "\r\n",
    "\t",
    "#",
    "{",
    "}",
    "[",
    "]",
    "\"",
    "(",
    ")",
    "=",
    "'",
    "#1",
    "$",
    ".",
    "E",
    "D",
    "1H",
    "999H",
    "element vertex 1000000000\n",
    "end_header\n",
    "facet normal 0 0 0\n",
    "v 1 2 3\n",
    "f 1 2 3\n",
    "f 1 99999 3\n",
    "\"knots\":[",
    "\"kind\":\"curve\"",
    "B_SPLINE_CURVE_WITH_KNOTS(",
    "126,",
    "128,",
    "\u{feff}",
    "\u{a0}",
    "\0",
    "\u{ff}",
];

/// One mutation of `input` (in place), chosen by `rng`; `seeds` are spliced in.
fn mutate(input: &mut Vec<u8>, rng: &mut Rng, seeds: &[Vec<u8>]) {
    let at = rng.below(input.len() + 1);
    match rng.below(9) {
        0 if !input.is_empty() => {
            let i = rng.below(input.len());
            input[i] ^= 1 << rng.below(8);
        }
        1 if !input.is_empty() => {
            let i = rng.below(input.len());
            input[i] = rng.next() as u8;
        }
        2 => {
            let t = TOKENS[rng.below(TOKENS.len())].as_bytes();
            input.splice(at..at, t.iter().copied());
        }
        3 if !input.is_empty() => {
            let end = (at + 1 + rng.below(64)).min(input.len());
            input.drain(at.min(end)..end);
        }
        4 if !input.is_empty() => {
            let start = rng.below(input.len());
            let end = (start + 1 + rng.below(256)).min(input.len());
            let chunk = input[start..end].to_vec();
            for _ in 0..1 + rng.below(8) {
                input.splice(at..at, chunk.iter().copied());
            }
        }
        5 => input.truncate(at),
        6 => {
            let digits = format!("{}", rng.next() >> rng.below(64));
            input.splice(at..at, digits.bytes());
        }
        7 if !seeds.is_empty() => {
            let other = &seeds[rng.below(seeds.len())];
            let from = rng.below(other.len() + 1);
            input.truncate(at);
            input.extend_from_slice(&other[from..]);
        }
        _ => {
            let i = rng.below(input.len() + 1);
            input.insert(i.min(input.len()), b"\n,; 0123456789.-eE"[rng.below(18)]);
        }
    }
    input.truncate(MAX_INPUT);
}

/// The input of iteration `k`: a seed with 1 to 8 mutations (iteration 0 of each seed unmutated).
fn input(k: u64, seeds: &[Vec<u8>]) -> Vec<u8> {
    let mut rng = Rng(k.wrapping_mul(0x2545_f491_4f6c_dd1d) ^ 0x5eed);
    let mut v = seeds[(k as usize) % seeds.len()].clone();
    if k >= seeds.len() as u64 {
        for _ in 0..1 + rng.below(8) {
            mutate(&mut v, &mut rng, seeds);
        }
    }
    v
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Every file under `dir` (recursively) whose extension is one of `exts`, read.
fn corpus(dirs: &[&str], exts: &[&str]) -> Vec<Vec<u8>> {
    let mut files = Vec::new();
    let mut stack: Vec<PathBuf> = dirs.iter().map(|d| repo().join(d)).collect();
    while let Some(d) = stack.pop() {
        let Ok(rd) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p
                .extension()
                .and_then(|x| x.to_str())
                .is_some_and(|x| exts.contains(&x.to_ascii_lowercase().as_str()))
            {
                files.push(p);
            }
        }
    }
    files.sort();
    files
        .iter()
        .filter_map(|f| std::fs::read(f).ok())
        .filter(|b| b.len() <= MAX_INPUT)
        .collect()
}

/// Meshes to start the mesh targets from: a tetrahedron in every writer's format, and a binary PLY.
fn mesh_seeds(ext: &str) -> Vec<Vec<u8>> {
    use fairfit::nurbs::Vec3;
    let n = Vec3::new(0.0, 0.0, 1.0);
    let mesh = fairfit::io::tessellate::Mesh {
        vertices: vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ],
        normals: vec![n; 4],
        triangles: vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]],
        polylines: Vec::new(),
    };
    use fairfit::io::mesh_write::{to_obj, to_ply, to_stl};
    match ext {
        "ply" => {
            let mut bin = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n\
property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                .to_vec();
            for v in [[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.]] {
                v.iter()
                    .for_each(|c| bin.extend_from_slice(&c.to_le_bytes()));
            }
            bin.push(3);
            [0i32, 1, 2]
                .iter()
                .for_each(|i| bin.extend_from_slice(&i.to_le_bytes()));
            vec![to_ply(&mesh).into_bytes(), bin]
        }
        "stl" => vec![to_stl(&mesh).unwrap()],
        _ => vec![to_obj(&mesh).into_bytes()],
    }
}

/// Runs one target: every input written to `name`, read by `read`, checked.
fn fuzz(
    target: &str,
    file_name: &str,
    seeds: Vec<Vec<u8>>,
    read: impl Fn(&Path) -> Option<String>,
) {
    assert!(!seeds.is_empty(), "{target}: empty seed corpus");
    let dir = std::env::temp_dir().join(format!("fairfit_fuzz_{target}_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(file_name);
    let secs = std::env::var("FAIRFIT_FUZZ_SECS")
        .ok()
        .and_then(|s| s.parse::<u64>().ok());
    let start_at = std::env::var("FAIRFIT_FUZZ_START")
        .ok()
        .and_then(|s| s.parse::<u64>().ok());
    let start = Instant::now();
    let (mut k, mut slowest) = (start_at.unwrap_or(0), (Duration::ZERO, 0));
    let mut count = 0u64;
    loop {
        let done = match secs {
            Some(s) => start.elapsed() >= Duration::from_secs(s),
            None => count >= DEFAULT_ITERATIONS,
        };
        if done {
            break;
        }
        let bytes = input(k, &seeds);
        std::fs::write(&path, &bytes).unwrap();
        LARGEST.store(0, Ordering::Relaxed);
        let t = Instant::now();
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| read(&path)));
        let took = t.elapsed();
        let largest = LARGEST.load(Ordering::Relaxed);
        if took > slowest.0 {
            slowest = (took, k);
        }
        let keep = || {
            let kept = dir.join(format!("crash_{k}_{file_name}"));
            std::fs::write(&kept, &bytes).unwrap();
            kept.display().to_string()
        };
        match outcome {
            Err(_) => panic!("{target}: iteration {k} panicked; input kept in {}", keep()),
            Ok(Some(msg)) if msg.contains('\n') || msg.is_empty() => {
                panic!(
                    "{target}: iteration {k}: error not one line: {msg:?} ({})",
                    keep()
                )
            }
            _ => {}
        }
        assert!(
            largest <= MAX_ALLOCATION,
            "{target}: iteration {k} allocated {largest} bytes at once; input kept in {}",
            keep()
        );
        k += 1;
        count += 1;
    }
    println!(
        "{target}: {count} inputs from iteration {} in {:.1} s, slowest {:.3} s (iteration {}), 0 crashes",
        start_at.unwrap_or(0),
        start.elapsed().as_secs_f64(),
        slowest.0.as_secs_f64(),
        slowest.1
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// The error message of a read, `None` for a successful one.
fn message<T>(r: fairfit::Result<T>) -> Option<String> {
    r.err().map(|e| e.to_string())
}

#[test]
fn fuzz_points_csv() {
    let seeds = corpus(&["examples/data"], &["csv", "dat", "txt"]);
    fuzz("points_csv", "p.csv", seeds, |p| {
        message(points::read_points(p))
    });
}

#[test]
fn fuzz_sections_xyz() {
    let seeds = corpus(
        &["examples/data/iea15mw_sections", "examples/data"],
        &["csv", "xyz"],
    );
    fuzz("sections_xyz", "c.xyz", seeds, |p| {
        message(sections::read_section_file(p)).or_else(|| message(mesh_read::read_mesh(p)))
    });
}

#[test]
fn fuzz_json() {
    let seeds = corpus(&["crates/fairfit/tests/data", "examples"], &["json"]);
    fuzz("json", "g.json", seeds, |p| {
        message(fairfit::io::read_geometry(p))
    });
}

#[test]
fn fuzz_mesh_ply() {
    fuzz("mesh_ply", "m.ply", mesh_seeds("ply"), |p| {
        message(mesh_read::read_mesh(p))
    });
}

#[test]
fn fuzz_mesh_stl() {
    fuzz("mesh_stl", "m.stl", mesh_seeds("stl"), |p| {
        message(mesh_read::read_mesh(p))
    });
}

#[test]
fn fuzz_mesh_obj() {
    fuzz("mesh_obj", "m.obj", mesh_seeds("obj"), |p| {
        message(mesh_read::read_mesh(p))
    });
}

#[test]
fn fuzz_step() {
    let seeds = corpus(&["crates/fairfit/tests/data"], &["step", "stp"]);
    fuzz("step", "c.step", seeds, |p| {
        message(cad_read::read_contents(p))
    });
}

#[test]
fn fuzz_iges() {
    let seeds = corpus(&["crates/fairfit/tests/data"], &["igs", "iges"]);
    fuzz("iges", "c.igs", seeds, |p| {
        message(cad_read::read_contents(p))
    });
}
