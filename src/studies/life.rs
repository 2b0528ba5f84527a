//! Lifetime fatigue of a channel from a normal-operation and a shutdown series (`windrive life` prints
//! it through [`crate::analysis::fatigue::lifetime`]): the wind climate, the gear tooth or bearing the
//! channel loads as the command line names them, and the reports of their lifetimes.

use crate::analysis::fatigue::lifetime::{BearingLife, GearLife, GearSpec};
use crate::analysis::fatigue::operating_hours::WindDistribution;
use crate::analysis::rating::bearing_set::{BearingSetError, BearingTable, RatedBearing};
use crate::analysis::rating::gear::{GearPair, MeshForce, Tooth};
use crate::analysis::rating::tooth_root::BasicRack;
use anyhow::bail;

/// A Weibull climate (shape, scale in m/s) if given, else a Rayleigh one with `mean_wind`, m/s.
pub fn wind_distribution(weibull: Option<&[f64]>, mean_wind: f64) -> anyhow::Result<WindDistribution> {
    Ok(match weibull {
        Some(w) if w.len() == 2 && w[0] > 0.0 && w[1] > 0.0 => WindDistribution::Weibull {
            shape: w[0],
            scale: w[1],
        },
        Some(w) => bail!("--weibull {w:?}: give shape,scale, both positive"),
        None if mean_wind > 0.0 => WindDistribution::Rayleigh { mean: mean_wind },
        None => bail!("--mean-wind {mean_wind}: must be positive"),
    })
}

/// The bearing table of the gearbox description `gearbox` (a preset or a file) read by `component`'s
/// channels; an error naming the gearbox when it cannot be read or has no roller set.
pub fn bearing_table(gearbox: &str, component: &str) -> anyhow::Result<BearingTable> {
    BearingTable::load(gearbox, component).map_err(|e| match e {
        BearingSetError::Gearbox(name, message) => anyhow::anyhow!("--gearbox {name}: {message}"),
        e => anyhow::anyhow!("--gearbox: {e}"),
    })
}

/// The bearing table of `--gearbox` and its bearing `name`, which must have a roller set.
pub fn named_bearing(gearbox: &str, component: &str, name: &str) -> anyhow::Result<(BearingTable, RatedBearing)> {
    let table = bearing_table(gearbox, component)?;
    let Some(b) = table.bearings.iter().find(|b| b.name == name).cloned() else {
        let names: Vec<&str> = table.bearings.iter().map(|b| b.name.as_str()).collect();
        bail!(
            "--bearing-of {name}: gearbox {} has no such bearing with a roller set; it has {}",
            gearbox,
            names.join(", ")
        );
    };
    Ok((table, b))
}

/// The gear options as the command line takes them: the pair's numbers as given (z1, z2, normal module
/// in mm, helix in degrees, face width in mm), its shifts and hob, which tooth and the load factors.
pub struct GearOptions<'a> {
    pub numbers: &'a [f64],
    pub internal: bool,
    pub shift: &'a [f64],
    pub rack: &'a [f64],
    pub y_fs: Option<&'a [f64]>,
    pub pressure_angle_deg: f64,
    /// sun, planet, ring or parallel.
    pub tooth: &'a str,
    pub member: Option<u8>,
    pub planets: u32,
    pub k_a: f64,
    pub k_gamma: f64,
    /// The channel is the force normal to the teeth (gearbox6dof's), not the transverse one.
    pub normal_force: bool,
}

/// The [`GearSpec`] of the options, checked: teeth ≥ 3, module and width > 0, two numbers each for
/// the shifts, the rack and Y_F,Y_S, a rack whose root radius is below its dedendum. The member
/// defaults to the tooth's: sun 1, planet 2 (1 on an internal pair), ring 2, parallel 1.
pub fn gear_spec(o: &GearOptions) -> anyhow::Result<GearSpec> {
    let g = o.numbers;
    if g.len() != 5 || g.iter().any(|v| !v.is_finite()) || g[0] < 3.0 || g[1] < 3.0 || g[2] <= 0.0 || g[4] <= 0.0 {
        bail!("--gear {g:?}: give z1,z2,module [mm],helix [deg],face width [mm] (teeth ≥ 3, module and width > 0)");
    }
    if o.shift.len() != 2 || o.rack.len() != 2 || o.y_fs.as_ref().is_some_and(|y| y.len() != 2) {
        bail!("--shift, --rack and --y-fs take two numbers each");
    }
    if !(o.rack[0] > 0.0 && o.rack[1] >= 0.0 && o.rack[1] < o.rack[0]) {
        bail!(
            "--rack {:?}: give the hob's dedendum h_fP > 0 and root radius 0 ≤ ρ_fP < h_fP, in modules",
            o.rack
        );
    }
    let pair = GearPair {
        z1: g[0] as u32,
        z2: g[1] as u32,
        internal: o.internal,
        module: g[2] * 1e-3,
        pressure_angle: o.pressure_angle_deg.to_radians(),
        helix_angle: g[3].to_radians(),
        face_width: g[4] * 1e-3,
        shift1: o.shift[0],
        shift2: o.shift[1],
        tip_diameters: None,
    };
    let tooth = match o.tooth {
        "sun" => Tooth::Sun,
        "planet" => Tooth::Planet,
        "ring" => Tooth::Ring,
        _ => Tooth::Parallel,
    };
    let spec = GearSpec {
        pair,
        tooth,
        member: o.member.unwrap_or(match tooth {
            Tooth::Planet if !o.internal => 2,
            Tooth::Ring => 2,
            _ => 1,
        }),
        y_fs: o.y_fs.as_ref().map(|y| (y[0], y[1])),
        rack: BasicRack {
            dedendum: o.rack[0],
            root_radius: o.rack[1],
            protuberance: 0.0,
        },
        planets: o.planets,
        k_a: o.k_a,
        k_gamma: o.k_gamma,
        force: if o.normal_force {
            MeshForce::Normal
        } else {
            MeshForce::Transverse
        },
    };
    Ok(spec)
}

/// The bearing's lifetime as the command prints it.
pub fn bearing_text(years: f64, b: &BearingLife) -> String {
    let mut text = format!(
        "{} bearing, C = {:.4e} N, ISO 281 L10 = (C/P)^{} million revolutions\n",
        if b.roller { "roller" } else { "ball" },
        b.capacity,
        if b.roller { "10/3" } else { "3" }
    );
    text.push_str(&format!(
        "{:<10} {:>14} {:>16} {:>14}\n",
        "case", "max P [N]", "revolutions", "damage"
    ));
    for c in &b.cases {
        text.push_str(&format!(
            "{:<10} {:>14.4e} {:>16.4e} {:>14.4e}\n",
            c.case, c.max_load, c.revolutions, c.damage
        ));
    }
    text.push_str(&format!(
        "lifetime: {:.4e} revolutions at P_eq = {:.4e} N (L10 {:.4e} revolutions)\n",
        b.revolutions, b.equivalent_load, b.l10_revolutions
    ));
    text.push_str(&format!(
        "{years}-year Miner damage {:.4e} ({:.1} % from shutdowns): L10 life {:.1} years\n",
        b.damage,
        100.0 * b.shutdown_share,
        b.l10_years
    ));
    text
}

/// `g`: the --gear numbers as given (module, helix and width in the user's units).
pub fn gear_text(years: f64, g: &[f64], spec: &GearSpec, r: &GearLife) -> String {
    let pair = &spec.pair;
    let mut text = format!(
        "gear {}/{} m_n {} mm β {}° b {} mm ({:?} tooth, {} load cycles per revolution): ε_α {:.3}, ε_β {:.3}\n",
        pair.z1,
        pair.z2,
        g[2],
        g[3],
        g[4],
        spec.tooth,
        r.cycles_per_revolution,
        pair.geometry().transverse_contact_ratio,
        pair.geometry().overlap_ratio
    );
    let root_note = match &r.root {
        None => "given".to_string(),
        Some(root) => format!(
            "ISO 6336-3 method B, member {}: s_Fn {:.2} mm, h_Fe {:.2} mm, ρ_F {:.2} mm",
            spec.member,
            root.chord * 1e3,
            root.bending_arm * 1e3,
            root.fillet_radius * 1e3
        ),
    };
    text.push_str(&format!("Y_F {:.4}, Y_S {:.4} ({root_note})\n", r.y_f, r.y_s));
    text.push_str(&format!(
        "{:<10} {:>12} {:>12} {:>16} {:>14} {:>14}\n",
        "case", "max σ_H MPa", "max σ_F MPa", "load cycles", "flank damage", "root damage"
    ));
    for c in &r.cases {
        text.push_str(&format!(
            "{:<10} {:>12.1} {:>12.1} {:>16.4e} {:>14.4e} {:>14.4e}\n",
            c.case,
            c.max_contact_stress / 1e6,
            c.max_root_stress / 1e6,
            c.load_cycles,
            c.flank_damage,
            c.root_damage
        ));
    }
    text.push_str(&format!(
        "lifetime: {:.4e} load cycles → Z_NT {:.3}, Y_NT {:.3}; limits σ_Hlim·Z_NT = {:.0} MPa, σ_FE·Y_M·Y_NT = {:.0} MPa\n",
        r.load_cycles,
        r.z_nt,
        r.y_nt,
        r.allowable_contact_stress / 1e6,
        r.allowable_root_stress / 1e6
    ));
    text.push_str(&format!(
        "{years}-year Miner damage: flank {:.4e} ({:.1} % from shutdowns), root {:.4e} ({:.1} % from shutdowns)\n",
        r.flank_damage,
        100.0 * r.flank_shutdown_share,
        r.root_damage,
        100.0 * r.root_shutdown_share
    ));
    text
}
