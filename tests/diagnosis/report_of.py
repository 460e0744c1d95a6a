"""A `Report` made from a report.json document, for the tests of the report's object and files
(no FMU): the docs' worked examples give real, complete reports."""
from musclesim.diagnosis.sections import (CalibrationSection, EvidenceSection, FitUnitSection,
                                          GapSection, IsolationSection, Report,
                                          ShrinkageSection, VerdictSection)


CONFIDENCE = ("set", "level", "probabilities", "calibrated", "gate", "calibration")


def report_of(doc):
    """The `Report` whose ``to_json()`` is `doc` (a report.json document)."""
    iso = EvidenceSection_ = confidence = None
    if "units" in doc:
        iso = IsolationSection(doc["located"], doc["units"], doc["regimes"])
    evidence = dict(doc.get("evidence") or {})
    if "calibration" in evidence:  # a calibrated set: its part apart, the credible set back
        confidence = {k: evidence[k] for k in CONFIDENCE}
        back = {"set": evidence.get("credible"), "level": evidence.get("credible_level")}
        evidence = {k: back.get(k, v) for k, v in evidence.items()
                    if k not in (*CONFIDENCE[2:], "credible", "credible_level")}
    if "candidates" in evidence:
        EvidenceSection_ = EvidenceSection(FitUnitSection(**doc["fit_unit"]), doc["effects"],
                                           evidence, doc["consistency"])
    return Report(doc["data_set"], doc["scenario"], doc["scalar_only"], doc["parts"]["train"],
                  doc["parts"]["held_out"], GapSection(**doc["gap"]),
                  CalibrationSection(**doc["calibration"]), iso, EvidenceSection_,
                  VerdictSection(doc["verdict"], doc["explanation"], doc["complete"],
                                 doc["noise_floor"], doc["selected"], doc["stand_ins"]),
                  ShrinkageSection(doc["shrinkage"], doc["aligned_samples"]), confidence)
