"""The packed FMUs read through fmpy, one instance per call: what tests that check documented values against
the FMUs share (tests/python/test_fmu_documentation.py, test_readme_numbers.py)."""

import shutil
import subprocess

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from conftest import ROOT


class Fmu:
    """One packed FMU, extracted once. `read` instantiates it, sets start values and inputs, leaves
    initialisation and returns the variables asked for; `step` takes one communication step first."""

    def __init__(self, path):
        self.md = read_model_description(str(path))
        self.dir = extract(str(path))
        self.vars = {v.name: v for v in self.md.modelVariables}

    def vr(self, name):
        return self.vars[name].valueReference

    def instance(self, start):
        """A new instance, initialised with `start`; the caller terminates and frees it."""
        s = FMU2Slave(guid=self.md.guid, unzipDirectory=self.dir,
                      modelIdentifier=self.md.coSimulation.modelIdentifier, instanceName="doc")
        s.instantiate()
        try:
            s.setupExperiment(startTime=0.0)
            for name, value in start.items():
                v = self.vars[name]
                setter = {"Real": s.setReal, "Integer": s.setInteger, "Boolean": s.setBoolean,
                          "String": s.setString}[v.type]
                setter([v.valueReference], [value])
            s.enterInitializationMode()
            s.exitInitializationMode()
        except Exception:
            s.freeInstance()
            raise
        return s

    def _get(self, s, names):
        out = {}
        for name in names:
            v = self.vars[name]
            getter = {"Real": s.getReal, "Integer": s.getInteger, "Boolean": s.getBoolean}[v.type]
            out[name] = getter([v.valueReference])[0]
        return out

    def read(self, start, names):
        s = self.instance(start)
        try:
            return self._get(s, names)
        finally:
            s.terminate()
            s.freeInstance()

    def step(self, start, h, names):
        s = self.instance(start)
        try:
            s.doStep(currentCommunicationPoint=0.0, communicationStepSize=h)
            return self._get(s, names)
        finally:
            s.terminate()
            s.freeInstance()


def packed(windrive, names):
    """Each named FMU of target/fmu (packed first if missing), extracted: yields {name: Fmu}, then removes the
    extracted folders. For a module-scoped fixture."""
    opened = {}
    for name in names:
        path = ROOT / "target" / "fmu" / f"{name}.fmu"
        if not path.is_file():
            subprocess.run([windrive, "pack", name], check=True, cwd=ROOT)
        opened[name] = Fmu(path)
    yield opened
    for f in opened.values():
        shutil.rmtree(f.dir, ignore_errors=True)
