-- A task's state apart from its payload: a job's progress, whether all its
-- tasks are done, and whether it is stranded are read from this index alone.
-- A row's later columns (status, progress, result) sit behind its payload,
-- which may hold a record suite of megabytes: read from the table, each poll
-- of a job walked every task's payload.
CREATE INDEX tasks_state ON tasks (computation_id, status, progress);
