"""A `Report` made from a report.json document, for the tests of the report's object and files
(no FMU): the docs' worked examples give real, complete reports."""
from musclesim.diagnosis.sections import (CalibrationSection, EvidenceSection, FitUnitSection,
                                          GapSection, IsolationSection, Report,
                                          ShrinkageSection, VerdictSection)


def report_of(doc):
    """The `Report` whose ``to_json()`` is `doc` (a report.json document)."""
    iso = EvidenceSection_ = None
    if "units" in doc:
        iso = IsolationSection(doc["located"], doc["units"], doc["regimes"])
    if "evidence" in doc:
        EvidenceSection_ = EvidenceSection(FitUnitSection(**doc["fit_unit"]), doc["effects"],
                                           doc["evidence"], doc["consistency"])
    return Report(doc["data_set"], doc["scenario"], doc["scalar_only"], doc["parts"]["train"],
                  doc["parts"]["held_out"], GapSection(**doc["gap"]),
                  CalibrationSection(**doc["calibration"]), iso, EvidenceSection_,
                  VerdictSection(doc["verdict"], doc["explanation"], doc["complete"],
                                 doc["noise_floor"], doc["selected"], doc["stand_ins"]),
                  ShrinkageSection(doc["shrinkage"], doc["aligned_samples"]))
