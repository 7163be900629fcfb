-- One row rewritten by the readiness probe after a failed write: it succeeds
-- only when the database can write again.
CREATE TABLE probe (
    id  INTEGER PRIMARY KEY CHECK (id = 1),
    at  TEXT NOT NULL
);
