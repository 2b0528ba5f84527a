//! What serde cannot check in a description: ranges, counts that must agree, planets that can be
//! assembled, bodies, beams, roller sets and meshes that make physical sense. Every message names
//! the field as `stage[i].field`.

use super::*;

impl Description {
    /// Checks serde cannot express; messages name the field as `stage[i].field`.
    pub(super) fn validate(&self) -> Result<(), String> {
        let m = &self.model;
        if m.slices == 0 || m.slices > 200 {
            return Err(format!("model.slices = {} outside 1..=200", m.slices));
        }
        positive_or_zero("model.gravity", m.gravity)?;
        for (name, v) in [
            ("model.mesh_damping_ratio", m.mesh_damping_ratio),
            ("model.bearing_damping_time", m.bearing_damping_time),
            ("model.shaft_damping_ratio", m.shaft_damping_ratio),
        ] {
            positive_or_zero(name, v)?;
        }
        positive("model.density", m.density)?;
        if let ForceLaw::Impact { exponent, penetration } = m.force_law {
            if !(1.0..=3.0).contains(&exponent) {
                return Err(format!("model.force_law.exponent = {exponent} outside [1, 3]"));
            }
            positive("model.force_law.penetration", penetration)?;
        }
        if self.stages.is_empty() {
            return Err("no [[stage]]: a gearbox needs at least one stage".into());
        }
        for (i, s) in self.stages.iter().enumerate() {
            let at = |f: &str| format!("stage[{}].{f}", i + 1);
            let toothing = match s {
                Stage::Planetary(p) => {
                    if !(2..=7).contains(&p.planets) {
                        return Err(format!("{} = {} outside 2..=7", at("planets"), p.planets));
                    }
                    if !((p.teeth.sun + p.teeth.ring) as usize).is_multiple_of(p.planets) {
                        return Err(format!(
                            "{}: (sun + ring) / planets = ({} + {}) / {} is not an integer: equally spaced planets cannot be assembled",
                            at("teeth"),
                            p.teeth.sun,
                            p.teeth.ring,
                            p.planets
                        ));
                    }
                    if !p.pin_errors_um.is_empty() && p.pin_errors_um.len() != p.planets {
                        return Err(format!(
                            "{} has {} values for {} planets",
                            at("pin_errors_um"),
                            p.pin_errors_um.len(),
                            p.planets
                        ));
                    }
                    for (b, name) in [(&p.carrier, "carrier"), (&p.planet, "planet"), (&p.sun, "sun")] {
                        check_body(b, &at(name))?;
                    }
                    if let Some(w) = &p.carrier_webs {
                        for (f, v) in [("torsional", w.torsional), ("radial", w.radial), ("tilting", w.tilting)] {
                            positive(&at(&format!("carrier_webs.{f}")), v)?;
                        }
                        if !(w.downwind_share > 0.0 && w.downwind_share < 1.0) {
                            return Err(format!(
                                "{} = {} outside (0, 1)",
                                at("carrier_webs.downwind_share"),
                                w.downwind_share
                            ));
                        }
                    }
                    if let Some(r) = &p.ring {
                        check_body(r, &at("ring"))?;
                    }
                    for (md, name) in [(&p.sun_planet, "sun_planet"), (&p.ring_planet, "ring_planet")] {
                        check_mesh(md, &at(name))?;
                    }
                    &p.toothing
                }
                Stage::Parallel(p) => {
                    check_body(&p.gear, &at("gear"))?;
                    check_body(&p.pinion, &at("pinion"))?;
                    check_mesh(&p.mesh, &at("mesh"))?;
                    &p.toothing
                }
            };
            positive(&at("module_mm"), toothing.module_mm)?;
            positive(&at("face_width_mm"), toothing.face_width_mm)?;
            if !(10.0..=35.0).contains(&toothing.pressure_angle_deg) {
                return Err(format!(
                    "{} = {} outside [10, 35]",
                    at("pressure_angle_deg"),
                    toothing.pressure_angle_deg
                ));
            }
            if !(0.0..=45.0).contains(&toothing.helix_angle_deg.abs()) {
                return Err(format!(
                    "{} = {} outside [−45, 45]",
                    at("helix_angle_deg"),
                    toothing.helix_angle_deg
                ));
            }
            positive_or_zero(&at("backlash_um"), toothing.backlash_um)?;
            positive_or_zero(&at("crowning_um"), toothing.crowning_um)?;
            finite(&at("lead_slope_um"), toothing.lead_slope_um)?;
        }
        if let Some(r) = &self.rotor {
            check_body(r, "rotor")?;
        }
        if let Some(g) = &self.generator {
            check_body(g, "generator")?;
        }
        Ok(())
    }
}

fn finite(name: &str, v: f64) -> Result<(), String> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(format!("{name} = {v} is not finite"))
    }
}

fn positive(name: &str, v: f64) -> Result<(), String> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(format!("{name} = {v} must be positive"))
    }
}

fn positive_or_zero(name: &str, v: f64) -> Result<(), String> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(format!("{name} = {v} must be ≥ 0"))
    }
}

fn check_support(s: &Support, at: &str) -> Result<(), String> {
    for (f, v) in [
        ("radial", s.radial),
        ("axial", s.axial),
        ("tilting", s.tilting),
        ("rotational", s.rotational),
    ] {
        positive_or_zero(&format!("{at}.{f}"), v)?;
    }
    if let Some(d) = s.damping {
        for v in d {
            positive_or_zero(&format!("{at}.damping"), v)?;
        }
    }
    Ok(())
}

fn check_body(b: &Body, at: &str) -> Result<(), String> {
    for (f, v) in [
        ("mass", b.mass),
        ("polar_inertia", b.polar_inertia),
        ("transverse_inertia", b.transverse_inertia),
    ] {
        if let Some(v) = v {
            positive(&format!("{at}.{f}"), v)?;
        }
    }
    if b.support.is_some() && !b.bearings.is_empty() {
        return Err(format!("{at}: give either bearings or support, not both"));
    }
    if let Some(s) = &b.support {
        check_support(s, &format!("{at}.support"))?;
    }
    for (k, br) in b.bearings.iter().enumerate() {
        finite(&format!("{at}.bearings[{}].position", k + 1), br.position)?;
        check_support(&br.stiffness(), &format!("{at}.bearings[{}]", k + 1))?;
        if let Some(r) = &br.rollers {
            check_rollers(r, &format!("{at}.bearings[{}].rollers", k + 1))?;
        }
        if br.name.is_empty() || !br.name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return Err(format!(
                "{at}.bearings[{}].name = {:?}: letters, digits and _ only",
                k + 1,
                br.name
            ));
        }
    }
    if let Some(s) = &b.shaft {
        positive(&format!("{at}.shaft.torsional"), s.torsional)?;
        for (f, v) in [("radial", s.radial), ("axial", s.axial), ("tilting", s.tilting)] {
            positive_or_zero(&format!("{at}.shaft.{f}"), v)?;
        }
        if let Some(c) = s.torsional_damping {
            positive_or_zero(&format!("{at}.shaft.torsional_damping"), c)?;
        }
        if let Some(beam) = &s.beam {
            check_beam(beam, s, &format!("{at}.shaft"))?;
        }
    }
    Ok(())
}

fn check_beam(beam: &Beam, s: &Shaft, at: &str) -> Result<(), String> {
    if s.radial > 0.0 || s.axial > 0.0 || s.tilting > 0.0 {
        return Err(format!(
            "{at}: give a beam or radial/axial/tilting stiffness, not both (the beam's come from its geometry)"
        ));
    }
    for (f, v) in [
        ("length_m", beam.length_m),
        ("outer_diameter_mm", beam.outer_diameter_mm),
        ("youngs_modulus", beam.youngs_modulus),
        ("shear_modulus", beam.shear_modulus),
    ] {
        positive(&format!("{at}.beam.{f}"), v)?;
    }
    if !(beam.inner_diameter_mm >= 0.0 && beam.inner_diameter_mm < beam.outer_diameter_mm) {
        return Err(format!(
            "{at}.beam.inner_diameter_mm = {}: 0 or more and below outer_diameter_mm = {}",
            beam.inner_diameter_mm, beam.outer_diameter_mm
        ));
    }
    if !(beam.from_m.is_finite() && beam.to_m.is_finite()) {
        return Err(format!("{at}.beam: from_m and to_m must be numbers"));
    }
    if !(1..=MAX_BEAM_ELEMENTS).contains(&beam.elements) {
        return Err(format!(
            "{at}.beam.elements = {} outside 1..={MAX_BEAM_ELEMENTS}",
            beam.elements
        ));
    }
    Ok(())
}

fn check_rollers(r: &Rollers, at: &str) -> Result<(), String> {
    if !(3..=200).contains(&r.count) {
        return Err(format!("{at}.count = {} outside 3..=200", r.count));
    }
    if !(1..=2).contains(&r.rows) {
        return Err(format!("{at}.rows = {}: 1 or 2", r.rows));
    }
    if !(1..=50).contains(&r.laminae) {
        return Err(format!("{at}.laminae = {} outside 1..=50", r.laminae));
    }
    for (f, v) in [
        ("diameter_mm", r.diameter_mm),
        ("length_mm", r.length_mm),
        ("pitch_diameter_mm", r.pitch_diameter_mm),
    ] {
        positive(&format!("{at}.{f}"), v)?;
    }
    if r.pitch_diameter_mm <= r.diameter_mm {
        return Err(format!(
            "{at}.pitch_diameter_mm = {} must exceed the roller diameter {} mm",
            r.pitch_diameter_mm, r.diameter_mm
        ));
    }
    if r.contact_angle_deg.is_nan() || r.contact_angle_deg.abs() >= 60.0 {
        return Err(format!(
            "{at}.contact_angle_deg = {} outside (−60, 60)",
            r.contact_angle_deg
        ));
    }
    positive_or_zero(&format!("{at}.row_spacing_mm"), r.row_spacing_mm)?;
    positive_or_zero(&format!("{at}.crowning_um"), r.crowning_um)?;
    finite(&format!("{at}.clearance_um"), r.clearance_um)?;
    finite(&format!("{at}.axial_clearance_um"), r.axial_clearance_um)?;
    let profile = match (r.profile_radius_mm, r.race_profile_radii_mm) {
        (None, None) => false,
        (Some(roller), Some(races)) => {
            if r.contact != Contact::Point {
                return Err(format!(
                    "{at}: profile_radius_mm and race_profile_radii_mm describe point contact: give contact = \"point\""
                ));
            }
            positive(&format!("{at}.profile_radius_mm"), roller)?;
            for (name, race) in ["inner", "outer"].into_iter().zip(races) {
                // a flat raceway (inf in TOML) is allowed: a crowned roller on a cylinder
                if race.is_nan() || race <= roller {
                    return Err(format!(
                        "{at}.race_profile_radii_mm: the {name} raceway's radius {race} mm must exceed the roller's \
                         profile_radius_mm = {roller} (a concave groove around a convex roller)"
                    ));
                }
            }
            if r.roller_stiffness.is_some() {
                return Err(format!(
                    "{at}: give roller_stiffness or the profile radii, not both (the radii give the stiffness)"
                ));
            }
            if r.crowning_um != 0.0 {
                return Err(format!(
                    "{at}.crowning_um: the profile radii describe the roller's crown already; leave crowning_um out"
                ));
            }
            let (rolling, across) = r.contact_radii();
            for (k, name) in ["inner", "outer"].into_iter().enumerate() {
                let across = across.map_or(f64::NAN, |a| a[k]);
                // the ellipse's shape does not depend on the modulus
                if crate::physics::hertz::EllipticContact::new(rolling[k], across, 1.0).is_none() {
                    return Err(format!(
                        "{at}: the roller and the {name} raceway conform so closely that the contact ellipse would be \
                         a million times longer than wide: give line contact with the osculation's gap as crowning_um"
                    ));
                }
            }
            true
        }
        _ => {
            return Err(format!(
                "{at}: give profile_radius_mm and race_profile_radii_mm = [inner, outer] together"
            ));
        }
    };
    match (r.contact, r.roller_stiffness) {
        (_, Some(c)) => positive(&format!("{at}.roller_stiffness"), c)?,
        (Contact::Point, None) if !profile => {
            return Err(format!(
                "{at}: point contact needs profile_radius_mm and race_profile_radii_mm, or roller_stiffness (N/m^1.5): \
                 ISO/TS 16281's line-contact constant does not apply"
            ));
        }
        _ => {}
    }
    Ok(())
}

fn check_mesh(m: &MeshData, at: &str) -> Result<(), String> {
    if m.stiffness.is_some() && m.torsional_stiffness.is_some() {
        return Err(format!("{at}: give stiffness or torsional_stiffness, not both"));
    }
    if m.damping.is_some() && m.torsional_damping.is_some() {
        return Err(format!("{at}: give damping or torsional_damping, not both"));
    }
    for (f, v) in [
        ("stiffness", m.stiffness),
        ("torsional_stiffness", m.torsional_stiffness),
        ("damping", m.damping),
        ("torsional_damping", m.torsional_damping),
    ] {
        if let Some(v) = v {
            positive_or_zero(&format!("{at}.{f}"), v)?;
        }
    }
    Ok(())
}
