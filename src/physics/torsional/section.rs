//! The model cut in its low-speed shaft ([`Section`]): either side alone, the cut's boundary as inputs,
//! and the energy and element forces that account for it.

use super::{
    Element, ElementLoad, ForceOutput, INPUT_CUT_ANGLE, INPUT_CUT_SPEED, INPUT_CUT_TORQUE, INPUT_GENERATOR_TORQUE,
    INPUT_ROTOR_TORQUE, Section, TorsionalModel,
};
use crate::solver::system::InputLoad;

impl TorsionalModel {
    /// This model cut in its low-speed shaft, keeping one side ([`Section`]). The rotor side keeps
    /// the rotor's inertia and loses every element; the drivetrain side loses the rotor's DOF, its
    /// LSS grounded at the cut boundary, whose angle and speed load the LSS's downstream body as
    /// inputs (exact for a linear shaft: k·g₀·θ_b + c·g₀·ω_b moved to the right-hand side).
    pub fn into_section(mut self, section: Section) -> Self {
        if self.section != Section::Whole || section == Section::Whole {
            return self;
        }
        self.section = section;
        let rotor = self.rotor;
        match section {
            Section::Whole => {}
            Section::Rotor => {
                self.mass.truncate(1);
                self.dof_names.truncate(1);
                self.speed_ratio.truncate(1);
                self.elements.clear();
                self.generator = 0;
                self.bodies = self
                    .bodies
                    .iter()
                    .enumerate()
                    .map(|(slot, b)| if slot == 0 { *b } else { None })
                    .collect();
                self.meshes.iter_mut().for_each(|m| *m = None);
                self.shafts.iter_mut().for_each(|s| *s = None);
                self.backlash = false;
                self.stiffness_variation = false;
                self.input_loads = vec![
                    InputLoad {
                        input: INPUT_ROTOR_TORQUE,
                        dof: 0,
                        gain: 1.0,
                    },
                    InputLoad {
                        input: INPUT_CUT_TORQUE,
                        dof: 0,
                        gain: -1.0,
                    },
                ];
            }
            Section::Drivetrain => {
                let shift = |d: usize| d - usize::from(d > rotor);
                self.mass.remove(rotor);
                self.dof_names.remove(rotor);
                self.speed_ratio.remove(rotor);
                let first_ratio = self.speed_ratio[0];
                let mut loads = vec![InputLoad {
                    input: INPUT_GENERATOR_TORQUE,
                    dof: shift(self.generator),
                    gain: -1.0,
                }];
                for e in &mut self.elements {
                    if let Some(pos) = e.coeffs.iter().position(|&(d, _)| d == rotor) {
                        // a shaft: linear, so its boundary share is exactly an external load
                        e.boundary = e.coeffs.remove(pos).1;
                        for &(d, g) in &e.coeffs {
                            for (input, gain) in [(INPUT_CUT_ANGLE, e.stiffness), (INPUT_CUT_SPEED, e.damping)] {
                                loads.push(InputLoad {
                                    input,
                                    dof: shift(d),
                                    gain: -g * e.boundary * gain,
                                });
                            }
                        }
                    }
                    e.coeffs.iter_mut().for_each(|(d, _)| *d = shift(*d));
                    if let Some(v) = &mut e.variation {
                        v.dof = shift(v.dof);
                    }
                    // deflections relative to the new DOF 0's rigid rotation; the grounded shaft
                    // has no rigid rotation to subtract
                    e.ratios = if e.boundary != 0.0 {
                        Vec::new()
                    } else {
                        e.coeffs
                            .iter()
                            .map(|&(d, _)| self.speed_ratio[d] / first_ratio)
                            .collect()
                    };
                }
                self.generator = shift(self.generator);
                self.bodies.iter_mut().enumerate().for_each(|(slot, b)| {
                    *b = if slot == 0 { None } else { b.map(|(d, f)| (shift(d), f)) };
                });
                self.input_loads = loads;
            }
        }
        self
    }

    /// The cut boundary's share of element `e`'s deflection and its rate at the boundary's angle and
    /// speed (zero unless the element is the grounded shaft of [`Section::Drivetrain`]).
    fn boundary_share(e: &Element, boundary: (f64, f64)) -> (f64, f64) {
        (e.boundary * boundary.0, e.boundary * boundary.1)
    }

    /// Element `e`'s force and elastic energy at the state (q, v) and the cut's (angle, speed)
    /// `boundary`: the one definition the outputs below read, alone or for every element at once.
    fn element_load(e: &Element, q: &[f64], v: &[f64], boundary: (f64, f64)) -> ElementLoad {
        let (angle, speed) = Self::boundary_share(e, boundary);
        let k = e.stiffness_at(q);
        let contact = e.contact(e.deflection(q) + angle);
        ElementLoad {
            force: e.force_in(k, contact, e.deflection(v) + speed),
            energy: 0.5 * k * contact.0 * contact.0,
        }
    }

    /// Element `i`'s force and elastic energy ([`Self::element_load`]): how an [`super::ElementTable`]
    /// reads the elements it does not pack.
    pub(super) fn element_load_of(&self, i: usize, q: &[f64], v: &[f64], boundary: (f64, f64)) -> ElementLoad {
        Self::element_load(&self.elements[i], q, v, boundary)
    }

    /// Kinetic energy plus the elastic energy of every element in contact, J; `boundary` is the
    /// cut's (angle, speed) for [`Section::Drivetrain`] (ignored otherwise).
    pub fn stored_energy(&self, q: &[f64], v: &[f64], boundary: (f64, f64)) -> f64 {
        let elastic: f64 = self
            .elements
            .iter()
            .map(|e| Self::element_load(e, q, v, boundary).energy)
            .sum();
        self.kinetic_energy(v) + elastic
    }

    fn kinetic_energy(&self, v: &[f64]) -> f64 {
        self.mass.iter().zip(v).map(|(m, w)| 0.5 * m * w * w).sum()
    }

    /// Force in element `o` (times its output factor) at the state (q, v) and the cut's (angle,
    /// speed) `boundary`.
    pub fn element_output(&self, o: Option<ForceOutput>, q: &[f64], v: &[f64], boundary: (f64, f64)) -> f64 {
        o.map_or(0.0, |o| {
            o.factor * Self::element_load(&self.elements[o.element], q, v, boundary).force
        })
    }

    /// [`Self::stored_energy`] from every element's load at the same state (an [`super::ElementTable`]'s),
    /// speeds `v`.
    pub fn stored_energy_of(&self, v: &[f64], loads: &[ElementLoad]) -> f64 {
        self.kinetic_energy(v) + loads.iter().map(|l| l.energy).sum::<f64>()
    }
}
