-- A tenant's jobs queued or running, counted at each submission against its
-- quota from this index alone, however many jobs it has finished.
CREATE INDEX jobs_live ON jobs (tenant) WHERE status IN ('queued', 'running');
