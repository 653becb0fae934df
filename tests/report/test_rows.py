"""Report rows (pedalrepro.report.rows and claims.check): one checked value, its CSV part, the
combined report and its summary; a NaN is refused."""

from __future__ import annotations

import pytest

from pedalrepro import report


def test_report_check_and_nan_rejected(tmp_path):
    # Sec 2.2.1 vertical COM NRMSD 3.6 %, one decimal: abs 0.05 (data/published/claims.yaml)
    row = report.check("nrmsd_com_z", 3.64)
    assert (row.id, row.status) == ("nrmsd_com_z", report.REPRODUCED)
    assert report.check("nrmsd_com_z", 3.66).status == report.DIFFERS
    with pytest.raises(ValueError, match="not finite"):
        report.check("nrmsd_com_z", float("nan"))
    path = tmp_path / "part.csv"
    report.write_rows([row], path)
    df = report.combine([path], tmp_path / "all.csv")
    assert report.summary(df) == {"reproduced": 1, "consistent": 0, "calibrated": 0,
                                  "differs": 0, "not reproducible here": 0}
