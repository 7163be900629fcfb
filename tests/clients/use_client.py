"""Drives a live topple through the Python client openapi-python-client
generates from openapi.yaml; type-checked with `mypy --strict` first.

Submits every kind, waits or polls, reads typed fields of each result,
downloads CSV and SVG, cancels a job; uploads a record file and computes a
time history naming it. Exits non-zero on the first surprise.

    python use_client.py BASE_URL SPECS_DIR
"""

import json
import sys
import time
from pathlib import Path
from uuid import UUID

from topple_client import AuthenticatedClient
from topple_client.api.jobs import cancel_job, create_job, get_job, get_plot, get_result
from topple_client.api.records import get_record, list_records
from topple_client.models import (
    ForensicExcitation,
    ForensicResult,
    ForensicSpec,
    FrictionSpectrumResult,
    FrictionSpectrumSpec,
    JobView,
    RecordDoc,
    RecordPage,
    RecordSpectrumResult,
    RecordSpectrumSpec,
    RecordView,
    SpectrumResult,
    SpectrumSpec,
    Status,
    TimeHistoryResult,
    TimeHistorySpec,
)
from topple_client.types import File, Unset


def check(condition: bool, what: str) -> None:
    if not condition:
        raise SystemExit(f"use_client.py: {what}")


def submitted(answer: object, what: str) -> JobView:
    check(isinstance(answer, JobView), f"{what}: not a job view: {answer!r}")
    assert isinstance(answer, JobView)
    return answer


def finished(client: AuthenticatedClient, job: JobView) -> JobView:
    deadline = time.monotonic() + 120
    while job.status in (Status.QUEUED, Status.RUNNING):
        check(time.monotonic() < deadline, f"job {job.id} did not finish")
        time.sleep(0.2)
        job = submitted(get_job.sync(job.id, client=client), "poll")
    check(job.status == Status.SUCCEEDED, f"job {job.id}: {job.status} {job.error!r}")
    return job


def main() -> None:
    base, specs = sys.argv[1], Path(sys.argv[2])
    client = AuthenticatedClient(base_url=base, token="unused", raise_on_unexpected_status=True)

    def spec(name: str) -> dict[str, object]:
        loaded: dict[str, object] = json.loads((specs / name).read_text())
        return loaded

    # A time history, waited for: the result comes inline, typed.
    history = TimeHistorySpec.from_dict(spec("locomotive_nonlinear.json"))
    job = submitted(create_job.sync(client=client, body=history, wait=30.0), "time history")
    check(job.status == Status.SUCCEEDED, f"time history {job.status}")
    inline = job.result
    check(isinstance(inline, TimeHistoryResult), f"inline result {type(inline)}")
    assert isinstance(inline, TimeHistoryResult)
    overturned: bool = inline.overturned
    impacts = inline.impacts
    first = impacts[0].t if not isinstance(impacts, Unset) and impacts else None
    check(overturned and first is not None and first > 0, "the locomotive overturns after an impact")
    check(inline.engine.name == "topple", "engine provenance")
    print(f"time history: overturned={overturned}, mode={inline.mode}, first impact t={first:.4f} s")

    # A spectrum, polled, then its typed transitions.
    spectrum_spec = SpectrumSpec.from_dict(
        {**spec("locomotive_spectrum_nonlinear.json"), "omega_ratio": {"from": 2, "to": 6, "steps": 3}}
    )
    job = finished(client, submitted(create_job.sync(client=client, body=spectrum_spec), "spectrum"))
    result = get_result.sync(job.id, client=client)
    check(isinstance(result, SpectrumResult), f"spectrum result {type(result)}")
    assert isinstance(result, SpectrumResult)
    transition = result.spectrum[0].transitions[0]
    a: float = transition.a_alpha_g
    print(f"spectrum: first transition at {a:.4f} αg ({transition.direction.value}), "
          f"minimum {result.spectrum[0].min_overturn_alpha_g}")

    # A friction spectrum and a forensic query.
    friction = FrictionSpectrumSpec.from_dict(spec("one_cosine_friction.json"))
    job = finished(client, submitted(create_job.sync(client=client, body=friction), "friction"))
    fr = get_result.sync(job.id, client=client)
    check(isinstance(fr, FrictionSpectrumResult), f"friction result {type(fr)}")
    assert isinstance(fr, FrictionSpectrumResult)
    demand = fr.points[0].peak_friction_demand
    print(f"friction spectrum: {len(fr.points)} amplitudes, first demand {demand}")
    forensic = ForensicSpec.from_dict(spec("point_reyes_forensic.json"))
    job = finished(client, submitted(create_job.sync(client=client, body=forensic), "forensic"))
    fo = get_result.sync(job.id, client=client)
    check(isinstance(fo, ForensicResult), f"forensic result {type(fo)}")
    assert isinstance(fo, ForensicResult)
    print(f"forensic: {len(fo.frequencies)} frequencies")
    on_record = ForensicSpec.from_dict(spec("point_reyes_forensic_record.json"))
    ojob = finished(client, submitted(create_job.sync(client=client, body=on_record), "forensic on a record"))
    fo_r = get_result.sync(ojob.id, client=client)
    check(isinstance(fo_r, ForensicResult), f"forensic record result {type(fo_r)}")
    assert isinstance(fo_r, ForensicResult)
    check(fo_r.excitation == ForensicExcitation.GROUND_MOTION, f"excitation {fo_r.excitation}")
    scales = fo_r.consistent_scale
    check(isinstance(scales, list) and len(scales) > 0, f"consistent scales {scales}")
    assert isinstance(scales, list)
    lowest: float = scales[0][0]
    check(isinstance(fo_r.record, RecordDoc), f"record {type(fo_r.record)}")
    print(f"forensic on a record: lowest consistent scale {lowest:.4f}")
    record = RecordSpectrumSpec.from_dict(spec("record_spectrum_one_sine.json"))
    rjob = finished(client, submitted(create_job.sync(client=client, body=record), "record spectrum"))
    rs = get_result.sync(rjob.id, client=client)
    check(isinstance(rs, RecordSpectrumResult), f"record spectrum result {type(rs)}")
    assert isinstance(rs, RecordSpectrumResult)
    size_m: float = rs.spectrum[0].r_m
    print(f"record spectrum: {len(rs.spectrum)} sizes from R = {size_m:.3f} m, PGA {rs.record.pga_g} g")

    # CSV and SVG. The result route answers JSON, CSV or SVG; the generator
    # parses its 200 as JSON, so CSV comes through the client's own httpx
    # session (same base URL and token), the figure through get_plot.
    csv = client.get_httpx_client().get(f"/v1/jobs/{job.id}/result", params={"format": "csv"})
    check(csv.status_code == 200 and csv.content.startswith(b"frequency_hz,"), "CSV")
    check(csv.headers["content-type"].startswith("text/csv"), "CSV content type")
    plot = get_plot.sync(job.id, client=client)
    check(isinstance(plot, File), f"plot {type(plot)}")
    assert isinstance(plot, File)
    check(b"<svg" in plot.payload.read(), "SVG")
    print(f"CSV {len(csv.content)} bytes, SVG fetched")

    # Cancel a large spectrum.
    big = SpectrumSpec.from_dict(
        {**spec("locomotive_spectrum_nonlinear.json"), "omega_ratio": {"from": 0.25, "to": 10, "steps": 1500}}
    )
    job = submitted(create_job.sync(client=client, body=big), "large spectrum")
    job_id: UUID = job.id
    canceled = submitted(cancel_job.sync(job_id, client=client), "cancel")
    check(canceled.status == Status.CANCELED, f"cancel: {canceled.status}")
    print("canceled a 1500-frequency spectrum")

    # A record file as it is (CSV), then a time history naming the stored
    # record. The generator sends no text/plain body (it types the file as
    # str, then reads `.payload` of it): the upload goes through the client's
    # own httpx session, its answer read through the generated RecordView.
    csv_file = specs / "records" / "ridge_station_090.csv"
    answer = client.get_httpx_client().post(
        "/v1/records", content=csv_file.read_bytes(), headers={"Content-Type": "text/plain"}
    )
    check(answer.status_code in (200, 201), f"upload: {answer.status_code} {answer.text[:300]}")
    uploaded = RecordView.from_dict(answer.json())
    samples: int = uploaded.samples
    pga: float = uploaded.pga_g
    check(samples == 3000 and abs(uploaded.dt - 0.01) < 1e-12, f"samples {samples}, dt {uploaded.dt}")
    check(uploaded.format_ == "csv" and uploaded.unit == "g", f"{uploaded.format_} in {uploaded.unit}")
    check(pga > 0 and abs(uploaded.pga_m_s2 - 9.81 * pga) < 1e-9 * uploaded.pga_m_s2, f"PGA {pga} g")
    stored = get_record.sync(uploaded.id, client=client)
    check(isinstance(stored, RecordView), f"record {type(stored)}")
    assert isinstance(stored, RecordView)
    check(stored.id == uploaded.id and stored.samples == samples, f"stored {stored.id}")
    page = list_records.sync(client=client)
    check(isinstance(page, RecordPage), f"records {type(page)}")
    assert isinstance(page, RecordPage)
    check(uploaded.id in [r.id for r in page.records], "the record is listed")
    on_file = TimeHistorySpec.from_dict({
        "kind": "time_history", "block": {"alpha": 0.15, "p": 2.0, "eta": 0.9},
        "ground_motion": {"record": uploaded.id}, "outputs": {"series": 50}})
    hjob = finished(client, submitted(create_job.sync(client=client, body=on_file, wait=30.0),
                                      "time history on a record"))
    read_back = get_result.sync(hjob.id, client=client)
    check(isinstance(read_back, TimeHistoryResult), f"time history on a record {type(read_back)}")
    assert isinstance(read_back, TimeHistoryResult)
    toppled: bool = read_back.overturned
    spec_motion = read_back.spec.ground_motion
    check(not isinstance(spec_motion, Unset) and spec_motion is not None
          and len(spec_motion.acc) == samples, "the result's spec holds the record's samples")
    print(f"record {uploaded.id}: {samples} samples, PGA {pga:.3f} g; "
          f"time history on it: overturned={toppled}")


if __name__ == "__main__":
    main()
