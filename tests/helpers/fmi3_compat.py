"""The FMI 3.0 GearedRotor-fmi3.fmu behind the FMI 2.0-shaped calls the test harness
(fmu_harness.py) and the tests make, so the same tests run on both .fmu files.

`Fmi3Slave` is FMPy's FMU3Slave with the FMI 2.0 names the suite uses mapped to their
FMI 3.0 counterparts (FMPy's own high-level calls underneath):

- setupExperiment stores the experiment; enterInitializationMode passes it to
  fmi3EnterInitializationMode (FMI 3.0 has no fmi3SetupExperiment);
- getReal/setReal -> Float64; getInteger/setInteger -> Int32, or Int64 for the
  Enumerations (FMI 3.0 reads and writes Enumerations as Int64);
- the FMU-state calls under their 2.0 spelling (getFMUstate, deSerializeFMUstate, ...);
- doStep keeps the out-arguments of fmi3DoStep (also when it raises), and
  getRealStatus(fmi2LastSuccessfulTime) answers with its lastSuccessfulTime;
- getRealOutputDerivatives -> fmi3GetOutputDerivatives.

FMI 2.0 calls without an FMI 3.0 counterpart (setRealInputDerivatives, the other status
getters) skip the test that makes them on the 3.0 .fmu (pytest.skip, with the reason).
"""

from __future__ import annotations

from ctypes import byref

import pytest
from fmpy.fmi3 import FMU3Slave, fmi3Boolean, fmi3Float64

FMI2_LAST_SUCCESSFUL_TIME = 2


def fmi2_only(what: str):
    """An FMI 2.0 function the FMI 3.0 standard does not have: skip the test here."""
    pytest.skip(f"FMI 2.0 only: {what}")


class Fmi3Slave(FMU3Slave):
    def __init__(self, enumerations: set[int], **kwargs):
        super().__init__(**kwargs)
        self._enums = set(enumerations)
        self._experiment = (None, 0.0, None)
        self.last_do_step = None  # (eventHandlingNeeded, terminate, earlyReturn, lastSuccessfulTime)

    # -- life cycle ------------------------------------------------------
    def setupExperiment(self, tolerance=None, startTime=0.0, stopTime=None):
        self._experiment = (tolerance, startTime, stopTime)

    def enterInitializationMode(self, tolerance=None, startTime=None, stopTime=None):
        tol, start, stop = self._experiment
        super().enterInitializationMode(
            tolerance=tol if tolerance is None else tolerance,
            startTime=start if startTime is None else startTime,
            stopTime=stop if stopTime is None else stopTime,
        )

    def fmi2FreeInstance(self, component):
        self.fmi3FreeInstance(component)

    # -- values ----------------------------------------------------------
    def getReal(self, vr):
        return self.getFloat64(list(vr))

    def setReal(self, vr, values):
        self.setFloat64(list(vr), list(values))

    def _split(self, vr):
        return [v for v in vr if v in self._enums], [v for v in vr if v not in self._enums]

    def getInteger(self, vr):
        vr = list(vr)
        out = {}
        enums, ints = self._split(vr)
        if ints:
            out.update(zip(ints, self.getInt32(ints)))
        if enums:
            out.update(zip(enums, self.getInt64(enums)))
        return [out[v] for v in vr]

    def setInteger(self, vr, values):
        vr, values = list(vr), list(values)
        ints = [(v, x) for v, x in zip(vr, values) if v not in self._enums]
        enums = [(v, x) for v, x in zip(vr, values) if v in self._enums]
        if ints:
            self.setInt32([v for v, _ in ints], [int(x) for _, x in ints])
        if enums:
            self.setInt64([v for v, _ in enums], [int(x) for _, x in enums])

    def getRealOutputDerivatives(self, vr, order):
        return self.getOutputDerivatives(list(vr), list(order))

    def setRealInputDerivatives(self, vr, order, value):
        fmi2_only("fmi2SetRealInputDerivatives (FMI 3.0 has no input derivatives)")

    # -- FMU state (FMI 2.0 spelling) ----------------------------------------
    def getFMUstate(self):
        return self.getFMUState()

    def setFMUstate(self, state):
        self.setFMUState(state)

    def freeFMUstate(self, state):
        self.freeFMUState(state)

    def serializeFMUstate(self, state):
        return self.serializeFMUState(state)

    def deSerializeFMUstate(self, serialized, state=None):
        return self.deserializeFMUState(serialized, state)

    # -- stepping ----------------------------------------------------------
    def doStep(self, currentCommunicationPoint, communicationStepSize,
               noSetFMUStatePriorToCurrentPoint=True):
        ev, term, early, last = fmi3Boolean(), fmi3Boolean(), fmi3Boolean(), fmi3Float64()
        try:
            return self.fmi3DoStep(
                self.component, currentCommunicationPoint, communicationStepSize,
                fmi3Boolean(noSetFMUStatePriorToCurrentPoint),
                byref(ev), byref(term), byref(early), byref(last),
            )
        finally:
            self.last_do_step = (ev.value, term.value, early.value, last.value)

    def fmi2DoStep(self, component, currentCommunicationPoint, communicationStepSize,
                   noSetFMUStatePriorToCurrentPoint=1):
        """The status of fmi3DoStep (raising above Warning, as FMPy's calls do)."""
        return self.doStep(currentCommunicationPoint, communicationStepSize,
                           noSetFMUStatePriorToCurrentPoint)

    def getRealStatus(self, kind):
        if kind != FMI2_LAST_SUCCESSFUL_TIME or self.last_do_step is None:
            fmi2_only(f"fmi2GetRealStatus({kind}) (FMI 3.0 has no status getters)")
        return self.last_do_step[3]

    def getStatus(self, kind):
        fmi2_only("fmi2GetStatus")

    def getBooleanStatus(self, kind):
        fmi2_only("fmi2GetBooleanStatus")
