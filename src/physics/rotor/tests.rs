use super::*;

#[test]
fn series_interpolation_and_hold() {
    let s = TorqueSeries {
        time: vec![0.0, 1.0, 2.0, 3.0],
        torque: vec![0.0, 1.0, 4.0, 9.0],
        pitching_moment: None,
        cubic: false,
    };
    assert_eq!(s.at(-1.0).0, 0.0);
    assert_eq!(s.at(1.5).0, 2.5);
    assert_eq!(s.at(5.0).0, 9.0);
    let c = TorqueSeries { cubic: true, ..s };
    // through the samples, and smoother than linear between them for t² data
    assert_eq!(c.at(2.0).0, 4.0);
    assert!((c.at(1.5).0 - 2.25).abs() < (2.5f64 - 2.25).abs());
}

#[test]
fn shutdown_sequence_times() {
    let s = Shutdown {
        time: 10.0,
        feather_rate: 0.14,
        pitch_delay: 0.0,
        trip_delay: 0.2,
        brake_delay: 0.5,
        brake_ramp_time: 0.6,
        brake_speed: 0.0,
    };
    assert!(s.generator_connected(10.1) && !s.generator_connected(10.2));
    assert_eq!(s.brake_command(10.4), 0.0);
    assert!((s.brake_command(10.8) - 0.5).abs() < 1e-12);
    assert_eq!(s.brake_command(12.0), 1.0);
    let never = Shutdown { time: -1.0, ..s };
    assert!(never.generator_connected(1e9) && never.brake_command(1e9) == 0.0);
}

/// A model of C's analytic rotor in steady wind with the sequences given.
fn model(shutdown: Shutdown, startup: Startup, pitch: f64) -> RotorModel {
    let rotor = Aerodynamics::Analytic(Rotor {
        radius: 40.0,
        lambda_min: 0.5,
    });
    RotorModel {
        source: std::sync::Arc::new(Source::Aero {
            rotor,
            mean_wind: 16.0,
            turbulence: None,
            pitch: PitchController {
                kp: 0.033498,
                ki: 0.0089128,
                gain_halving_pitch: 0.11,
                min_pitch: 0.0,
                max_pitch: std::f64::consts::FRAC_PI_2,
                max_rate: 0.14,
            },
            target: PitchTarget::Speed(180.0),
            tilt: TiltModel::new(40.0, 80.0, 0.0, 0.0, 0.0),
            gear_ratio: 92.0,
            blades: None,
        }),
        shutdown,
        startup,
        state: PitchState { pitch, integral: 0.0 },
        sequence: SequenceState {
            offline: startup.planned(),
            brake_from: None,
        },
        time: 0.0,
        azimuth: 0.0,
    }
}

const NO_SHUTDOWN: Shutdown = Shutdown {
    time: -1.0,
    feather_rate: 0.14,
    pitch_delay: 0.0,
    trip_delay: 0.0,
    brake_delay: 0.0,
    brake_ramp_time: 0.6,
    brake_speed: 0.0,
};

/// A start-up idles at its initial pitch until the start command, then pitches towards fine pitch
/// no faster than its rate; the generator stays off-line until the rotor reaches the connect speed,
/// and once online stays online (a latch, not a speed band).
#[test]
fn startup_sequence() {
    let startup = Startup {
        time: 2.0,
        pitch_rate: 0.035,
        connect_speed: 1.9,
    };
    let mut m = model(NO_SHUTDOWN, startup, std::f64::consts::FRAC_PI_2);
    m.advance(0.0, 2.0);
    assert_eq!(m.state.pitch, std::f64::consts::FRAC_PI_2);
    assert!(!m.generator_connected());
    m.advance(0.5, 1.0);
    assert!(
        (m.state.pitch - (std::f64::consts::FRAC_PI_2 - 0.035)).abs() < 1e-9,
        "{}",
        m.state.pitch
    );
    m.advance(1.89, 1.0);
    assert!(!m.generator_connected());
    m.advance(1.9, 0.01);
    assert!(m.generator_connected());
    m.advance(0.5, 1.0);
    assert!(m.generator_connected());
    // online, the controller's own rate applies again
    let before = m.state.pitch;
    m.advance(0.5, 0.1);
    assert!((before - m.state.pitch - 0.014).abs() < 1e-9);
    // no start-up planned: online from the start
    assert!(model(NO_SHUTDOWN, Startup::NONE, 0.0).generator_connected());
}

/// A grid loss feathers only after the pitch delay; a normal stop brakes once the rotor has slowed
/// to the brake speed, not before the brake delay, and ramps from there.
#[test]
fn pitch_delay_and_speed_triggered_brake() {
    let grid_loss = Shutdown {
        time: 1.0,
        pitch_delay: 0.2,
        ..NO_SHUTDOWN
    };
    let mut m = model(grid_loss, Startup::NONE, 0.2);
    m.advance(1.9, 1.1);
    assert!(!m.generator_connected());
    let held = m.state.pitch;
    m.advance(1.9, 0.1);
    assert!((m.state.pitch - held).abs() < 0.14 * 0.1 + 1e-12);
    m.advance(1.9, 0.5);
    assert!(
        (m.state.pitch - (held + 0.14 * 0.5)).abs() < 0.02,
        "{} {held}",
        m.state.pitch
    );
    let stop = Shutdown {
        time: 1.0,
        brake_delay: 2.0,
        brake_speed: 0.2,
        ..NO_SHUTDOWN
    };
    let mut m = model(stop, Startup::NONE, 0.2);
    m.advance(0.1, 2.0);
    assert_eq!(m.brake_command(), 0.0, "slow already, but before the brake delay");
    m.advance(1.0, 2.0);
    assert_eq!(m.brake_command(), 0.0, "after the delay, but fast");
    m.advance(0.15, 0.01);
    m.advance(1.0, 0.3);
    assert!((m.brake_command() - 0.5).abs() < 0.02, "{}", m.brake_command());
}

/// Above rated wind the trimmed pitch gives rated power at rated speed; below it, fine pitch.
#[test]
fn trim_pitch_holds_rated_power() {
    let rotor = Aerodynamics::Analytic(Rotor {
        radius: 40.0,
        lambda_min: 0.5,
    });
    let (p, w) = (2e6, 16f64.to_radians() * 6.0);
    let v_rated = rated_wind_speed(&rotor, p, w).unwrap();
    assert_eq!(trim_pitch(&rotor, v_rated - 1.0, p, w, 1.5), 0.0);
    let v = v_rated + 0.5;
    assert!(rotor.torque(w, v, 0.0) * w > 1.01 * p);
    let beta = trim_pitch(&rotor, v, p, w, 1.5);
    assert!(
        beta > 0.0 && ((rotor.torque(w, v, beta) * w) / p - 1.0).abs() < 1e-9,
        "{beta}"
    );
}

/// No shear: the thrust acts at the hub. Shear α > 0 lifts it above the hub.
#[test]
fn tilt_offset_from_shear() {
    assert!(TiltModel::new(40.0, 80.0, 0.0, 0.0, 0.0).thrust_offset.abs() < 1e-9);
    let e = TiltModel::new(40.0, 80.0, 0.2, 0.0, 0.0).thrust_offset;
    // small-shear estimate: e ≈ α R² / (2 z_hub) = 2 m
    assert!(e > 1.5 && e < 2.5, "{e}");
}
