-- Long text is compressed with lz4 rather than pglz where the server has it
-- (PostgreSQL 14 and later, built with lz4): result documents, specs (which
-- may hold records), task payloads and results, record samples. Compressing a
-- 10 kB time-history result with pglz took about a third of the database's
-- CPU per small job. Only what is written from now on is compressed so; a
-- server without lz4 keeps pglz (the statement fails inside the block and
-- nothing changes).
DO $$
BEGIN
    EXECUTE 'ALTER TABLE results ALTER COLUMN body SET COMPRESSION lz4';
    EXECUTE 'ALTER TABLE computations ALTER COLUMN spec SET COMPRESSION lz4';
    EXECUTE 'ALTER TABLE tasks ALTER COLUMN payload SET COMPRESSION lz4';
    EXECUTE 'ALTER TABLE tasks ALTER COLUMN result SET COMPRESSION lz4';
    EXECUTE 'ALTER TABLE record_samples ALTER COLUMN acc SET COMPRESSION lz4';
EXCEPTION WHEN OTHERS THEN
    RAISE NOTICE 'lz4 compression not available: %', SQLERRM;
END
$$;
