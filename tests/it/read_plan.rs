//! A host reading a long array of Real variables (a recorder's row) gets what it gets reading them one
//! by one, to the bit: the torsional FMU resolves such an array once into where each value comes from,
//! and must resolve it again for a model built anew (another preset, another section); the gearbox FMU
//! checks its model and loads once per array.

use windrive::fmi2::fmu::slave::{NoLog, Slave};
use windrive::fmi2::fmu::variables::{Causality, VarType};
use windrive::models::torsional::vr;
use windrive::slaves::gearbox6dof::Gearbox6dofSlave;
use windrive::slaves::torsional::TorsionalSlave;

/// Every Real variable with a value, as an array and one by one, as bits.
fn both_ways<S: Slave>(s: &mut S) -> (Vec<u64>, Vec<u64>) {
    let vrs: Vec<u32> = S::VARIABLES
        .iter()
        .filter(|v| v.ty == VarType::Real)
        .map(|v| v.vr)
        .collect();
    assert!(vrs.len() > 40, "{} Real variables", vrs.len());
    let mut array = vec![0.0; vrs.len()];
    s.get_reals(&vrs, &mut array).unwrap();
    let one_by_one = vrs.iter().map(|&r| s.get_real(r).unwrap().to_bits()).collect();
    (array.into_iter().map(f64::to_bits).collect(), one_by_one)
}

#[test]
fn an_array_reads_what_its_values_read_one_by_one_across_rebuilds() {
    let mut s = TorsionalSlave::instantiate(None);
    s.set_real(vr::MESH_BACKLASH, 1e-4, &mut NoLog).unwrap();
    s.initialize(0.0, &mut NoLog).unwrap();
    let mut t: f64 = 0.0;
    let h = 1e-3;
    // D whole, then C cut at its LSS (other bodies, the cut's inputs in the shaft torque), then D again,
    // then D with its meshes' stiffness following their roll (the elements whose stiffness the packed
    // loads ask of the element itself)
    for (preset, section, variation) in [
        ("D", "whole", 0.0),
        ("C", "drivetrain", 0.0),
        ("D", "whole", 0.0),
        ("D", "whole", 0.2),
    ] {
        s.set_string(vr::PRESET, preset, &mut NoLog).unwrap();
        s.set_string(vr::SECTION, section, &mut NoLog).unwrap();
        s.set_real(vr::MESH_STIFFNESS_VARIATION, variation, &mut NoLog).unwrap();
        for k in 0..300 {
            let (array, one_by_one) = both_ways(&mut s);
            assert_eq!(array, one_by_one, "{preset} {section}, step {k}");
            s.set_real(vr::ROTOR_TORQUE, 1e6 * (1.0 + (7.0 * t).sin()), &mut NoLog)
                .unwrap();
            s.set_real(vr::CUT_SPEED, 1.5 + 0.1 * (3.0 * t).cos(), &mut NoLog)
                .unwrap();
            s.set_real(vr::BRAKE_COMMAND, if k > 150 { 1.0 } else { 0.0 }, &mut NoLog)
                .unwrap();
            s.do_step(t, h, &mut NoLog).unwrap();
            t += h;
        }
    }
    // a reference that is no Real variable fails the array as it fails alone
    let mut values = [0.0; 9];
    let mut vrs = [vr::HSS_TORQUE; 9];
    vrs[4] = 99_999;
    assert!(s.get_reals(&vrs, &mut values).is_err());
    assert!(s.get_real(99_999).is_err());
    // fewer values than references: the values there are, as one by one, and no panic
    let vrs = [
        vr::HSS_TORQUE,
        vr::LSS_TORQUE,
        vr::STORED_ENERGY,
        vr::GEAR_RATIO,
        vr::ROTOR_SPEED,
    ]
    .repeat(2);
    let mut short = [0.0; 9];
    s.get_reals(&vrs, &mut short).unwrap();
    for (&r, v) in vrs.iter().zip(&short) {
        assert_eq!(v.to_bits(), s.get_real(r).unwrap().to_bits(), "vr {r}");
    }
}

/// Parameters read as a long array while the model cannot be built (a backlash below full fidelity)
/// read as they do one by one; the outputs fail alike.
#[test]
fn parameters_read_as_an_array_while_the_model_cannot_be_built() {
    let mut s = TorsionalSlave::instantiate(None);
    s.set_string(vr::FIDELITY, "2", &mut NoLog).unwrap();
    s.set_real(vr::MESH_BACKLASH, 1e-4, &mut NoLog).unwrap();
    assert!(s.initialize(0.0, &mut NoLog).is_err());
    let parameters: Vec<u32> = TorsionalSlave::VARIABLES
        .iter()
        .filter(|v| v.ty == VarType::Real && v.causality == Causality::Parameter)
        .map(|v| v.vr)
        .collect();
    assert!(parameters.len() >= 8, "{} Real parameters", parameters.len());
    let mut array = vec![0.0; parameters.len()];
    s.get_reals(&parameters, &mut array).unwrap();
    for (&r, a) in parameters.iter().zip(&array) {
        assert_eq!(a.to_bits(), s.get_real(r).unwrap().to_bits(), "vr {r}");
    }
    let mut outputs = [0.0; 8];
    assert!(s.get_reals(&[vr::HSS_TORQUE; 8], &mut outputs).is_err());
}

/// The gearbox FMU's every Real variable as one array and one by one, to the bit, after every step of
/// a torque ramp and a brake application, across a rebuild (lamina-table bearings, then linear ones),
/// and before the model is built (parameters alone).
#[test]
fn a_gearbox_array_reads_what_its_values_read_one_by_one() {
    use windrive::models::gearbox6dof::vr;
    let mut g = Gearbox6dofSlave::instantiate(None);
    g.set_integer(vr::SLICES, 5, &mut NoLog).unwrap();
    let (array, one_by_one) = both_ways(&mut g);
    assert_eq!(array, one_by_one, "before initialisation");
    g.initialize(0.0, &mut NoLog).unwrap();
    let rated = g.get_real(vr::INITIAL_ROTOR_TORQUE).unwrap();
    let ratio = g.get_real(vr::GEAR_RATIO).unwrap();
    let mut t: f64 = 0.0;
    for model in ["lamina-table", "linear"] {
        g.set_string(vr::BEARING_MODEL, model, &mut NoLog).unwrap();
        for k in 0..40 {
            let (array, one_by_one) = both_ways(&mut g);
            assert_eq!(array, one_by_one, "{model}, step {k}");
            g.set_real(vr::ROTOR_TORQUE, rated * (1.0 - 0.01 * k as f64), &mut NoLog)
                .unwrap();
            g.set_real(vr::GENERATOR_TORQUE, rated / ratio, &mut NoLog).unwrap();
            g.set_real(vr::BRAKE_COMMAND, if k > 20 { 1.0 } else { 0.0 }, &mut NoLog)
                .unwrap();
            g.do_step(t, 1e-3, &mut NoLog).unwrap();
            t += 1e-3;
        }
    }
    // a reference that is no Real variable fails the array as it fails alone
    let mut values = [0.0; 9];
    let mut refs = [vr::HSS_TORQUE; 9];
    refs[4] = 99_999;
    assert!(g.get_reals(&refs, &mut values).is_err());
    assert!(g.get_real(99_999).is_err());
}

/// Every element output of the torsional FMU reads through the packed element table: its loads are the
/// model's own element loads (`element_output`, `stored_energy`) to the bit, for every preset, fidelity
/// and section, with backlash and with the meshes' stiffness following their roll.
#[test]
fn the_packed_element_loads_are_the_models_to_the_bit() {
    use windrive::physics::drivetrain::Drivetrain;
    use windrive::physics::torsional::{ElementTable, Fidelity, ForceOutput, ModelOptions, Section, TorsionalModel};
    let mut rng = crate::common::Rng(0x9e37_79b9_7f4a_7c15);
    let mut random = move || rng.symmetric();
    let mut models = 0;
    for preset in ["A", "B", "C", "D"] {
        for fidelity in [Fidelity::Two, Fidelity::Five, Fidelity::Full] {
            for (mesh_backlash, mesh_stiffness_variation) in [(0.0, 0.0), (1e-4, 0.0), (0.0, 0.2), (1e-4, 0.2)] {
                for section in [Section::Whole, Section::Drivetrain] {
                    let options = ModelOptions {
                        mesh_backlash,
                        mesh_stiffness_variation,
                        ..ModelOptions::default()
                    };
                    let drivetrain = Drivetrain::preset(preset).unwrap();
                    // backlash and varying stiffness need the full model
                    let Ok(model) = TorsionalModel::new(&drivetrain, fidelity, &options) else {
                        continue;
                    };
                    let model = model.into_section(section);
                    let table = ElementTable::new(&model);
                    let mut loads = Vec::new();
                    for _ in 0..40 {
                        // a rigid rotation of up to a thousand radians with deflections of up to 1e-3 rad
                        // (inside and outside the backlash) and speeds about it
                        let (turn, spin) = (1000.0 * random(), 2.0 * random());
                        let q: Vec<f64> = model.speed_ratio.iter().map(|r| r * turn + 1e-3 * random()).collect();
                        let v: Vec<f64> = model.speed_ratio.iter().map(|r| r * spin + 1e-2 * random()).collect();
                        let boundary = (1e-3 * random(), 1e-2 * random());
                        table.loads(&model, &q, &v, boundary, &mut loads);
                        assert_eq!(loads.len(), model.elements.len());
                        for (e, load) in loads.iter().enumerate() {
                            let output = Some(ForceOutput {
                                element: e,
                                factor: 1.0,
                            });
                            let expected = model.element_output(output, &q, &v, boundary).to_bits();
                            let what = format!("{preset} {fidelity:?} {section:?} {options:?}, element {e}");
                            assert_eq!(load.force.to_bits(), expected, "{what}");
                            assert_eq!(
                                table.load(&model, e, &q, &v, boundary).force.to_bits(),
                                expected,
                                "{what}"
                            );
                        }
                        assert_eq!(
                            model.stored_energy_of(&v, &loads).to_bits(),
                            model.stored_energy(&q, &v, boundary).to_bits()
                        );
                    }
                    models += 1;
                }
            }
        }
    }
    assert!(models >= 30, "{models} models");
}
