"""Rotor torque source made with PythonFMU (a tool nobody here wrote): zero until ramp_start, then a
linear ramp to torque_final over ramp_time; brake command 0; grid connected. Raises an FMU error from
fail_time on (negative = never), to test how masters handle an FMU that fails mid-run; pauses
pause_length seconds of wall time once at pause_time and crashes the whole process (SIGSEGV) at crash_time, to test what a
master keeps of its results when a third-party FMU takes it down."""
import os
import signal
import time

from pythonfmu import Boolean, Fmi2Causality, Fmi2Slave, Fmi2Variability, Real


class PyRotor(Fmi2Slave):
    author = "windrive tests"
    description = "Rotor torque ramp source (PythonFMU)"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.torque_final = 385000.0
        self.ramp_start = 0.0055
        self.ramp_time = 0.5
        self.fail_time = -1.0
        self.pause_time = -1.0
        self.pause_length = 0.5
        self.crash_time = -1.0
        self.rotor_torque = 0.0
        self.brake_command = 0.0
        self.connected = True
        for name in ("torque_final", "ramp_start", "ramp_time", "fail_time", "pause_time", "pause_length", "crash_time"):
            self.register_variable(Real(name, causality=Fmi2Causality.parameter, variability=Fmi2Variability.tunable))
        self.register_variable(Real("rotor_torque", causality=Fmi2Causality.output))
        self.register_variable(Real("brake_command", causality=Fmi2Causality.output))
        self.register_variable(Boolean("connected", causality=Fmi2Causality.output))

    def do_step(self, current_time, step_size):
        if 0.0 <= self.fail_time <= current_time:
            return False
        if 0.0 <= self.pause_time <= current_time:
            time.sleep(self.pause_length)
            self.pause_time = -1.0
        if 0.0 <= self.crash_time <= current_time:
            os.kill(os.getpid(), signal.SIGSEGV)
        t = current_time + step_size
        x = min(max((t - self.ramp_start) / self.ramp_time, 0.0), 1.0)
        self.rotor_torque = self.torque_final * x
        return True
