use fairfit::fit::corners::*;
use fairfit::fit::noise::estimate_noise;
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let pts = fairfit::io::read_points(&a[1]).unwrap().points;
    let ang: f64 = a[2].parse().unwrap();
    let closed = a.get(3).map(|s| s == "closed").unwrap_or(false);
    let tol = 1e-3 * fairfit::fit::points::bounding_box_extent(&pts);
    let ne = estimate_noise(&pts);
    let s = CornerScale::new(tol, ne, ang);
    println!("n {} tol {tol:e} noise {ne:?} scale {s:?}", pts.len());
    let t = std::time::Instant::now();
    let c = corners_at_tolerance(&pts, closed, ang, tol);
    println!("{:?} {:?}", c.len(), t.elapsed());
    for &i in c.iter().take(20) {
        println!("  {i} {:?}", pts[i]);
    }
}
