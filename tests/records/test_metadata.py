"""The recording's metadata (:class:`isorock.records.metadata.RecordMetadata`): one definition, read
and written by the manifest, carried by a record and a PEER row, hashed into the jobs' parameters."""

from __future__ import annotations

import json
import math
from dataclasses import fields

import pytest

from isorock.errors import CatalogError
from isorock.records.manifest import MANIFEST_COLUMNS, ManifestEntry
from isorock.records.metadata import METADATA_COLUMNS, RecordMetadata
from isorock.records.spec import RecordFile, RecordSpec

META = RecordMetadata(
    rsn=6,
    mw=6.95,
    mechanism="strike slip",
    rjb_km=6.09,
    rrup_km=6.09,
    vs30_m_s=213.44,
    luf_hz=0.25,
    year=1940,
)
FILE = RecordFile(path="/r/a.AT2", format="peer-at2")


def test_the_columns_are_the_fields_in_their_order():
    assert METADATA_COLUMNS == ("rsn", "mw", "mechanism", "rjb_km", "rrup_km", "vs30_m_s", "luf_hz", "year")
    assert MANIFEST_COLUMNS[-len(METADATA_COLUMNS) :] == METADATA_COLUMNS
    assert all(f.default in (None, "") for f in fields(RecordMetadata))


def test_unknowns_are_left_out_and_named_values_keep_every_key():
    assert RecordMetadata().to_dict() == {}
    assert RecordMetadata(mw=7.0, mechanism="").to_dict() == {"mw": 7.0}
    assert list(META.to_dict()) == list(METADATA_COLUMNS)
    assert META.with_names("Imperial Valley-02", "El Centro") == {
        "rsn": 6, "mw": 6.95, "mechanism": "strike slip", "rjb_km": 6.09, "rrup_km": 6.09,
        "vs30_m_s": 213.44, "luf_hz": 0.25, "earthquake": "Imperial Valley-02", "year": 1940,
        "station": "El Centro",
    }  # fmt: skip
    assert RecordMetadata().with_names("", "")["rsn"] is None


def test_the_manifest_cells_read_back():
    cells = META.cells()
    assert cells == {
        "rsn": "6", "mw": "6.95", "mechanism": "strike slip", "rjb_km": "6.09", "rrup_km": "6.09",
        "vs30_m_s": "213.44", "luf_hz": "0.25", "year": "1940",
    }  # fmt: skip
    assert RecordMetadata.from_cells(cells, "m.csv", 2) == META
    assert RecordMetadata.from_cells({}, "m.csv", 2) == RecordMetadata()
    assert RecordMetadata().cells() == dict.fromkeys(METADATA_COLUMNS, "")


@pytest.mark.parametrize(
    "cell, says",
    [
        ({"rsn": "0"}, "rsn='0' is not a record sequence number"),
        ({"rsn": "1.5"}, "rsn='1.5' is not a record sequence number"),
        ({"mw": "big"}, "mw='big' is not a magnitude"),
        ({"rjb_km": "-1"}, "rjb_km='-1' is not a distance >= 0 km"),
        ({"vs30_m_s": "0"}, "vs30_m_s='0' is not a velocity > 0 m/s"),
        ({"luf_hz": "nan"}, "luf_hz='nan' is not a frequency > 0 Hz"),
        ({"year": "1940.5"}, "year='1940.5' is not a year"),
    ],
)
def test_a_bad_cell_is_refused_with_its_line(cell, says):
    with pytest.raises(CatalogError, match=says) as err:
        RecordMetadata.from_cells(cell, "m.csv", 7)
    assert "7" in str(err.value)


def test_the_store_attributes():
    assert META.store_attrs() == {
        "rsn": 6, "mw": 6.95, "mechanism": "strike slip", "rjb_km": 6.09, "rrup_km": 6.09,
        "vs30_m_s": 213.44, "luf_hz": 0.25,
    }  # fmt: skip
    plain = RecordMetadata().store_attrs()
    assert plain["rsn"] == -1 and plain["mechanism"] == "" and math.isnan(plain["luf_hz"])
    assert list(plain) == [c for c in METADATA_COLUMNS if c != "year"]


def test_a_manifest_row_is_flat():
    e = ManifestEntry(file="a.AT2", id="A", metadata=META, line=3)
    d = e.to_dict()
    assert list(d) == [
        "file", "table1_id", "id", "format", "units", "dt_s", "column", "event", "station", "component",
        "note", "sha256", "azimuth_deg", *METADATA_COLUMNS, "line",
    ]  # fmt: skip
    assert d["luf_hz"] == 0.25 and d["line"] == 3


def test_a_record_without_metadata_keeps_its_parameters():
    """The jobs' config hash: the parameters of a record without metadata are those of before it."""
    spec = RecordSpec(id="X", label="x", files=(FILE,), metadata=RecordMetadata(year=1994))
    d = spec.to_dict()
    assert list(d) == [
        "id", "label", "event", "station", "component", "strike_deg", "strike_source", "tp_source", "year",
        "catalog_id", "table1_pga_g", "table1_pgv_m_s", "table1_tp_s", "files", "source",
    ]  # fmt: skip
    assert d["year"] == 1994 and spec.year == 1994
    assert RecordSpec.from_dict(json.loads(json.dumps(d))) == spec
    assert RecordSpec(id="X", label="x").to_dict()["year"] is None


def test_a_record_with_metadata_adds_what_is_known():
    spec = RecordSpec(id="RSN6", label="x", files=(FILE,), metadata=META)
    d = spec.to_dict()
    assert list(d)[-9:] == [
        "files",
        "source",
        "rsn",
        "mw",
        "mechanism",
        "rjb_km",
        "rrup_km",
        "vs30_m_s",
        "luf_hz",
    ]
    assert d["year"] == 1940
    assert RecordSpec.from_dict(json.loads(json.dumps(d))) == spec
