//! The ground edge's back-scatter and directional albedo against the angle of incidence, single
//! vs multiple microfacet scattering: the reference curve of validation/results/edge_reflectance.
//!
//! ```sh
//! cargo run --release --example edge_reflectance > validation/results/edge_reflectance/edge_reflectance.csv
//! cargo run --release --example edge_reflectance -- --plot validation/results/edge_reflectance
//! ```
//!
//! For each roughness α ∈ {0.1, 0.3, 0.6, 1.0} and incidence θ = 0…85° from air (η = 1.5208,
//! the edge material of the scenes), with wo the direction back to the laser:
//! - back-scatter p(wo → wo) = f*(wo, wo)·cos θ (1/sr), the flux per steradian sent straight
//!   back towards the source, for the single-scattering model the tracer used before
//!   (`RoughDielectric`, separable G₁G₁), for the walk's first order (height-correlated G₂)
//!   and for all orders (`MultipleScatteringDielectric::f_adjoint_cos`, mean of 2·10⁵
//!   one-walk estimates, with its standard error);
//! - directional albedo, reflected and transmitted: the single-scattering model's by its own
//!   sampler (weight G₁(wi)), the multiple-scattering model's from 2·10⁵ sampled walks.
//!
//! Prints CSV on stdout; with `--plot DIR` also writes the figures
//! `backscatter_alpha_K.png/.svg` (K = 0…3 for the four α) and `albedo.png/.svg` into DIR
//! (which must exist). Fixed seeds: the output is reproducible.

use std::path::PathBuf;

use glassscan::optics::microfacet::RoughDielectric;
use glassscan::optics::microfacet_walk::{MultipleScatteringDielectric, MAX_EVENTS};
use glassscan::optics::uniform_stream::{KeyedStream, UniformSource};
use glassscan::plot::error_bars::{ErrorBars, Series};
use nalgebra::Vector3;
use rayon::prelude::*;

/// Relative index of the ground edge (glass/air) in the shipped scenes.
const ETA: f64 = 1.5208;
const ALPHAS: [f64; 4] = [0.1, 0.3, 0.6, 1.0];
/// Monte Carlo samples per (α, θ) and estimate.
const N: u64 = 200_000;

/// One row of the table.
struct Row {
    alpha: f64,
    theta_deg: f64,
    back_single: f64,
    back_first: f64,
    back_multiple: f64,
    back_multiple_se: f64,
    single_r: f64,
    single_t: f64,
    multiple_r: f64,
    multiple_t: f64,
}

fn row(a: usize, t: usize) -> Row {
    let alpha = ALPHAS[a];
    let theta_deg = 5.0 * t as f64;
    let theta = theta_deg.to_radians();
    // Incidence in the x–z plane; wo points back to the laser.
    let wo = Vector3::new(theta.sin(), 0.0, theta.cos());
    let single = RoughDielectric::new(alpha, ETA);
    let multiple = MultipleScatteringDielectric::new(alpha, ETA);
    let key = |purpose: u64| KeyedStream::new(&[2026, a as u64, t as u64, purpose]);

    let back_single = single.f_adjoint(&wo, &wo) * wo.z;
    let back_first = multiple.f_adjoint_cos_single(&wo, &wo);
    let mut s = key(0);
    let (mut sum, mut sum2) = (0.0, 0.0);
    for _ in 0..N {
        let v = multiple.f_adjoint_cos_orders(&wo, &wo, 2, MAX_EVENTS, &mut s);
        sum += v;
        sum2 += v * v;
    }
    let n = N as f64;
    let mean = sum / n;
    let back_multiple_se = ((sum2 / n - mean * mean).max(0.0) / (n - 1.0)).sqrt();

    let mut s = key(1);
    let (mut single_r, mut single_t) = (0.0, 0.0);
    for _ in 0..N {
        let u = [s.next_uniform(), s.next_uniform(), s.next_uniform()];
        if let Some(x) = single.sample(&wo, u[0], [u[1], u[2]]) {
            let w = x.f_adjoint * x.wi.z.abs() / x.pdf;
            if x.reflected {
                single_r += w / n;
            } else {
                single_t += w / n;
            }
        }
    }
    let mut s = key(2);
    let (mut multiple_r, mut multiple_t) = (0.0, 0.0);
    for _ in 0..N {
        if let Some(x) = multiple.sample(&wo, &mut s, None) {
            if x.reflected {
                multiple_r += x.weight / n;
            } else {
                multiple_t += x.weight / n;
            }
        }
    }
    Row {
        alpha,
        theta_deg,
        back_single,
        back_first,
        back_multiple: back_first + mean,
        back_multiple_se,
        single_r,
        single_t,
        multiple_r,
        multiple_t,
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let plot_dir = match args.as_slice() {
        [] => None,
        [flag, dir] if flag == "--plot" => Some(PathBuf::from(dir)),
        _ => return Err("usage: edge_reflectance [--plot DIR]".into()),
    };
    let rows: Vec<Row> = (0..ALPHAS.len())
        .flat_map(|a| (0..18).map(move |t| (a, t)))
        .collect::<Vec<_>>()
        .into_par_iter()
        .map(|(a, t)| row(a, t))
        .collect();
    println!(
        "alpha,incidence_deg,backscatter_single,backscatter_first_order,backscatter_multiple,\
         backscatter_multiple_se,albedo_single_reflected,albedo_single_transmitted,\
         albedo_multiple_reflected,albedo_multiple_transmitted"
    );
    for r in &rows {
        println!(
            "{},{},{:.6e},{:.6e},{:.6e},{:.2e},{:.5},{:.5},{:.5},{:.5}",
            r.alpha,
            r.theta_deg,
            r.back_single,
            r.back_first,
            r.back_multiple,
            r.back_multiple_se,
            r.single_r,
            r.single_t,
            r.multiple_r,
            r.multiple_t
        );
    }
    if let Some(dir) = plot_dir {
        let series = |name: &str, f: &dyn Fn(&Row) -> (f64, f64)| -> Vec<Series> {
            ALPHAS
                .iter()
                .map(|&alpha| Series {
                    name: format!("α = {alpha}, {name}"),
                    points: rows
                        .iter()
                        .filter(|r| r.alpha == alpha)
                        .map(|r| {
                            let (m, e) = f(r);
                            (r.theta_deg, m, e)
                        })
                        .collect(),
                })
                .collect()
        };
        for (a, &alpha) in ALPHAS.iter().enumerate() {
            let curve = |f: &dyn Fn(&Row) -> (f64, f64)| -> Vec<(f64, f64, f64)> {
                rows.iter()
                    .filter(|r| r.alpha == alpha)
                    .map(|r| {
                        let (m, e) = f(r);
                        (r.theta_deg, m, e)
                    })
                    .collect()
            };
            let figure = ErrorBars {
                title: format!("Ground edge α = {alpha}: back-scatter towards the laser"),
                x_desc: "incidence from air (deg), η = 1.5208".into(),
                y_desc: "f*(wo, wo)·cos θ (1/sr)".into(),
                series: vec![
                    Series {
                        name: "multiple scattering (walk)".into(),
                        points: curve(&|r| (r.back_multiple, r.back_multiple_se)),
                    },
                    Series {
                        name: "walk's first order (height-correlated G₂)".into(),
                        points: curve(&|r| (r.back_first, 0.0)),
                    },
                    Series {
                        name: "single scattering before (separable G₁G₁)".into(),
                        points: curve(&|r| (r.back_single, 0.0)),
                    },
                ],
            };
            glassscan::plot::save(&figure, &dir, &format!("backscatter_alpha_{a}"))?;
        }
        let albedo = series("multiple, reflected", &|r| (r.multiple_r, 0.0));
        glassscan::plot::save(
            &ErrorBars {
                title: "Ground edge: reflected albedo (η = 1.5208, from air)".into(),
                x_desc: "incidence (deg)".into(),
                y_desc: "reflected flux fraction".into(),
                series: albedo,
            },
            &dir,
            "albedo",
        )?;
    }
    Ok(())
}
