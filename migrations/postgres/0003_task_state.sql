-- A task's state apart from its payload: a job's progress, whether all its
-- tasks are done, and whether it is stranded are read from this index alone
-- (an index-only scan where the visibility map allows).
CREATE INDEX tasks_state ON tasks (computation_id, status, progress);
