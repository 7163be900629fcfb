-- Records: accelerograms uploaded by tenants. The samples are stored once,
-- under their content's id (blake3 of dt and the samples in m/s²), however
-- many tenants upload them; each tenant's upload is a row of `records` with
-- its own name and metadata. `job_records` says which records a job named,
-- so that a record in use by a live job is not deleted.
CREATE TABLE record_samples (
    id       TEXT PRIMARY KEY,
    dt       REAL NOT NULL,
    samples  INTEGER NOT NULL,
    acc      BLOB NOT NULL            -- the samples, m/s², f64 little-endian
);

CREATE TABLE records (
    entry       TEXT PRIMARY KEY,     -- UUIDv7 of the upload: orders a listing
    tenant      TEXT NOT NULL,
    id          TEXT NOT NULL REFERENCES record_samples (id),
    name        TEXT NOT NULL,
    meta        TEXT NOT NULL,        -- the record's metadata document (JSON)
    created_at  TEXT NOT NULL,
    UNIQUE (tenant, id)
);
CREATE INDEX records_tenant ON records (tenant, entry);
CREATE INDEX records_id ON records (id);

CREATE TABLE job_records (
    job_id     TEXT NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    record_id  TEXT NOT NULL,
    PRIMARY KEY (job_id, record_id)
);
CREATE INDEX job_records_record ON job_records (record_id);
