"""Variable-speed generator torque law made with PythonFMU: region 2, T = k * omega^2 from the speed
input, zero before t_on (so a master's initial-value propagation does not matter: see test_master.py)."""
from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real


class PyController(Fmi2Slave):
    author = "windrive tests"
    description = "Region-2 generator torque law (PythonFMU)"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.k = 0.1876
        self.t_on = 0.0055
        self.generator_speed = 0.0
        self.generator_torque = 0.0
        self.register_variable(Real("k", causality=Fmi2Causality.parameter, variability=Fmi2Variability.tunable))
        self.register_variable(Real("t_on", causality=Fmi2Causality.parameter, variability=Fmi2Variability.tunable))
        self.register_variable(Real("generator_speed", causality=Fmi2Causality.input))
        self.register_variable(Real("generator_torque", causality=Fmi2Causality.output))

    def do_step(self, current_time, step_size):
        on = current_time + step_size > self.t_on
        self.generator_torque = self.k * self.generator_speed ** 2 if on else 0.0
        return True
