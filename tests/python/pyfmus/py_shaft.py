"""Damped two-inertia shaft made with PythonFMU: torque input on J1, J2 free; internal RK4 substeps.
Outputs both speeds and the shaft torque k*(phi1 - phi2) + c*(w1 - w2)."""
from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real


class PyShaft(Fmi2Slave):
    author = "windrive tests"
    description = "Damped two-inertia shaft (PythonFMU)"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.J1, self.J2, self.k, self.c = 4.0e6, 1.0e6, 2.0e8, 2.0e6
        self.torque = 0.0
        self.speed_1 = self.speed_2 = self.shaft_torque = 0.0
        self.x = [0.0, 0.0, 0.0]  # twist, w1, w2
        for name in ("J1", "J2", "k", "c"):
            self.register_variable(Real(name, causality=Fmi2Causality.parameter, variability=Fmi2Variability.fixed))
        self.register_variable(Real("torque", causality=Fmi2Causality.input))
        for name in ("speed_1", "speed_2", "shaft_torque"):
            self.register_variable(Real(name, causality=Fmi2Causality.output))

    def f(self, x):
        ts = self.k * x[0] + self.c * (x[1] - x[2])
        return [x[1] - x[2], (self.torque - ts) / self.J1, ts / self.J2]

    def do_step(self, current_time, step_size):
        n = 20
        h = step_size / n
        x = self.x
        for _ in range(n):
            k1 = self.f(x)
            k2 = self.f([a + h / 2 * b for a, b in zip(x, k1)])
            k3 = self.f([a + h / 2 * b for a, b in zip(x, k2)])
            k4 = self.f([a + h * b for a, b in zip(x, k3)])
            x = [a + h / 6 * (p + 2 * q + 2 * r + s) for a, p, q, r, s in zip(x, k1, k2, k3, k4)]
        self.x = x
        self.speed_1, self.speed_2 = x[1], x[2]
        self.shaft_torque = self.k * x[0] + self.c * (x[1] - x[2])
        return True
