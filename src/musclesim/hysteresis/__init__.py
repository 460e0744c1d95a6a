"""The SMA wire's hysteresis as a study: FORC identification from the identification runs and its
validation on the virtual wire (§forc-identification), the loop explorer (steady peak-to-peak strain
of cycled temperature bands), the long-duration drift test (§drift) and the timing of the Preisach
core.
"""
from musclesim.hysteresis.drift import Protocol as DriftProtocol
from musclesim.hysteresis.drift import drift_main
from musclesim.hysteresis.drift import run as drift_test
from musclesim.hysteresis.identify import identify as identify_forc
from musclesim.hysteresis.identify import identify_main
from musclesim.hysteresis.loops import loops as band_loops
from musclesim.hysteresis.loops import loops_main, parse_band
from musclesim.hysteresis.timing import format_preisach as format_preisach_timing
from musclesim.hysteresis.timing import preisach as preisach_timing
from musclesim.hysteresis.validation import report as validation_report

__all__ = ["identify_forc", "identify_main", "band_loops", "loops_main", "parse_band",
           "preisach_timing", "format_preisach_timing", "validation_report", "DriftProtocol",
           "drift_main", "drift_test"]
