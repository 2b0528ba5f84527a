//! The torque demand a variable-speed turbine's controller sends to the converter, from the
//! low-pass filtered generator speed ω_f. Two laws:
//!
//! - `Law`: the NREL baseline (Jonkman's DISCON, OpenFAST r-test) region law. Region 1 (below
//!   cut-in) 0; region 1½ a line from cut-in to the start of region 2; region 2 k·ω² (the optimal
//!   tip-speed-ratio law); region 2½ a line through the synchronous speed of a `slip` induction
//!   machine ending at rated torque; region 3 (ω_f ≥ rated) constant power P/ω_f. Torque ≤ max.
//! - `Speed`: a PI regulator holding the generator at a reference speed (the thesis's Simulink
//!   generator "controls the rotor speed"): what a playback rotor, whose torque does not answer
//!   the speed, needs. Gains from the drivetrain's inertia J at the generator and a bandwidth ω_n:
//!   K_p = 2ζω_n·J, K_i = ω_n²·J, ζ = 0.7; integrator clamped so the torque stays in [0, max].

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TorqueLaw {
    pub cut_in: f64,
    pub region2_start: f64,
    /// k of region 2, N·m/(rad/s)².
    pub k: f64,
    /// Start of region 3 (DISCON's VS_RtGnSp, 99 % of the pitch controller's reference).
    pub rated_speed: f64,
    pub rated_power: f64,
    /// Zero-torque speed of the region-2½ line: rated_speed / (1 + slip).
    pub sync_speed: f64,
    pub max_torque: f64,
}

impl TorqueLaw {
    /// The law for rated power and speed, region-2 gain k, cut-in speed and the region-2½ slip.
    pub fn new(rated_power: f64, rated_speed: f64, k: f64, cut_in: f64, slip: f64, max_torque: f64) -> Self {
        let sync_speed = rated_speed / (1.0 + slip);
        let mut law = TorqueLaw {
            cut_in,
            region2_start: cut_in,
            k,
            rated_speed,
            rated_power,
            sync_speed,
            max_torque,
        };
        // region 1½ spans 30 % above cut-in (DISCON: 871/670 rpm) unless region 2½ starts sooner
        law.region2_start = (1.3 * cut_in).min(law.transition_speed());
        law
    }

    fn slope25(&self) -> f64 {
        self.rated_power / self.rated_speed / (self.rated_speed - self.sync_speed)
    }

    /// Where k·ω² meets the region-2½ line (OpenFAST ServoDyn's VS_TrGnSp); the rated speed when
    /// k·ω² lies above the line everywhere below rated.
    pub fn transition_speed(&self) -> f64 {
        let s = self.slope25();
        let disc = s * (s - 4.0 * self.k * self.sync_speed);
        if self.k <= 0.0 {
            return self.sync_speed;
        }
        if disc < 0.0 {
            return self.rated_speed;
        }
        ((s - disc.sqrt()) / (2.0 * self.k)).min(self.rated_speed)
    }

    pub fn torque(&self, w: f64) -> f64 {
        let t = if w >= self.rated_speed {
            self.rated_power / w
        } else if w <= self.cut_in {
            0.0
        } else if w < self.region2_start {
            self.k * self.region2_start.powi(2) * (w - self.cut_in) / (self.region2_start - self.cut_in)
        } else if w < self.transition_speed() {
            self.k * w * w
        } else {
            self.slope25() * (w - self.sync_speed)
        };
        t.clamp(0.0, self.max_torque)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpeedRegulator {
    pub reference: f64,
    pub kp: f64,
    pub ki: f64,
    pub max_torque: f64,
}

impl SpeedRegulator {
    pub fn new(reference: f64, inertia: f64, bandwidth: f64, max_torque: f64) -> Self {
        SpeedRegulator {
            reference,
            kp: 2.0 * 0.7 * bandwidth * inertia,
            ki: bandwidth * bandwidth * inertia,
            max_torque,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum TorqueControl {
    Law(TorqueLaw),
    Speed(SpeedRegulator),
}

impl TorqueControl {
    /// Torque demand from the filtered speed and the speed regulator's integral (unused by `Law`).
    pub fn demand(&self, w_filtered: f64, integral: f64) -> f64 {
        match self {
            TorqueControl::Law(l) => l.torque(w_filtered),
            TorqueControl::Speed(r) => (r.kp * (w_filtered - r.reference) + integral).clamp(0.0, r.max_torque),
        }
    }

    /// d(integral)/dt: zero for `Law`, and zero while the demand is clamped and the error would
    /// push it further (anti-windup).
    pub fn integral_rate(&self, w_filtered: f64, integral: f64) -> f64 {
        match self {
            TorqueControl::Law(_) => 0.0,
            TorqueControl::Speed(r) => {
                let e = w_filtered - r.reference;
                let raw = r.kp * e + integral;
                if (raw >= r.max_torque && e > 0.0) || (raw <= 0.0 && e < 0.0) {
                    0.0
                } else {
                    r.ki * e
                }
            }
        }
    }

    /// The integral that makes the demand `torque` at speed `w` (a start in equilibrium).
    pub fn integral_for(&self, w: f64, torque: f64) -> f64 {
        match self {
            TorqueControl::Law(_) => 0.0,
            TorqueControl::Speed(r) => torque - r.kp * (w - r.reference),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The NREL 5 MW law (Jonkman's DISCON: VS_RtGnSp 121.6805 rad/s, VS_Rgn2K 2.332287,
    /// VS_SlPc 10 %, VS_RtPwr 5 296 610 W, cut-in 70.16224 rad/s) gives VS_SySp 110.619 rad/s,
    /// VS_TrGnSp 119.014 rad/s, Slope15 921.83 and Slope25 3935.04 N·m/(rad/s).
    #[test]
    fn nrel_5mw_constants() {
        let law = TorqueLaw::new(5_296_610.0, 121.6805, 2.332287, 70.16224, 0.10, 47_402.91);
        assert!((law.sync_speed - 110.619).abs() < 1e-3);
        assert!(
            (law.transition_speed() - 119.014).abs() < 1e-3,
            "{}",
            law.transition_speed()
        );
        assert!((law.slope25() - 3935.04).abs() < 0.05, "{}", law.slope25());
        assert!((law.region2_start - 91.21091).abs() < 1e-3);
        let slope15 = law.k * law.region2_start.powi(2) / (law.region2_start - law.cut_in);
        assert!((slope15 - 921.83).abs() < 0.05, "{slope15}");
        // continuous at every region boundary
        for w in [law.cut_in, law.region2_start, law.transition_speed(), law.rated_speed] {
            let (a, b) = (law.torque(w - 1e-9), law.torque(w + 1e-9));
            assert!((a - b).abs() < 1e-3 * law.max_torque, "jump at {w}: {a} vs {b}");
        }
        assert_eq!(law.torque(60.0), 0.0);
        assert!((law.torque(130.0) - 5_296_610.0 / 130.0).abs() < 1e-9);
    }

    #[test]
    fn speed_regulator_clamps_and_stops_winding_up() {
        let c = TorqueControl::Speed(SpeedRegulator::new(100.0, 50.0, 1.0, 1000.0));
        let i = c.integral_for(100.0, 400.0);
        assert!((c.demand(100.0, i) - 400.0).abs() < 1e-12);
        assert_eq!(c.demand(200.0, i), 1000.0);
        assert_eq!(c.integral_rate(200.0, 2000.0), 0.0);
        assert!(c.integral_rate(101.0, i) > 0.0);
    }
}
