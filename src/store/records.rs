//! Records: accelerograms uploaded by tenants. The samples are stored once
//! under their content's id, however many tenants upload them; each tenant's
//! upload has its own name and metadata, and belongs to it as a job does
//! (another tenant's record does not exist).

use sqlx::{
    AssertSqlSafe, ColumnIndex, Connection, Decode, Encode, Executor, IntoArguments, Row, Type,
};
use uuid::Uuid;

use super::dialect::{Dialect, fill};
use super::sql::{RowsAffected, SqlStore};
use super::{BoxFuture, StoreError};

/// A record's samples: its sampling interval, s, and accelerations, m/s².
pub type Samples = (f64, Vec<f64>);

/// A tenant's record as stored (without its samples).
#[derive(Clone, Debug, PartialEq)]
pub struct RecordRow {
    /// The content's id: dt and samples in m/s².
    pub id: String,
    /// The upload's own id (UUIDv7): listings are ordered by it, and page by it.
    pub entry: Uuid,
    /// The name the tenant's upload gave it.
    pub name: String,
    /// The metadata document (JSON text): format, unit, peaks, warnings.
    pub meta: String,
    /// RFC 3339.
    pub created_at: String,
}

/// An upload to store.
#[derive(Clone, Copy, Debug)]
pub struct NewRecord<'a> {
    /// Whose upload it is.
    pub tenant: &'a str,
    /// The content's id.
    pub id: &'a str,
    /// The upload's id, if the tenant does not have the record yet.
    pub entry: Uuid,
    /// Sampling interval, s.
    pub dt: f64,
    /// Samples, m/s².
    pub acc: &'a [f64],
    /// Its name.
    pub name: &'a str,
    /// Its metadata document (JSON text).
    pub meta: &'a str,
    /// RFC 3339.
    pub now: &'a str,
}

/// What a deletion did.
#[derive(Clone, Debug, PartialEq)]
pub enum RecordDeleted {
    /// The tenant's record is gone (its samples too, once no tenant has it).
    Gone,
    /// The tenant has no such record.
    NotFound,
    /// Live jobs of the tenant use it (their ids).
    InUse(Vec<Uuid>),
}

/// Storage of records.
pub trait RecordStore: Send + Sync {
    /// Stores the tenant's upload: the samples once (by id), and the tenant's
    /// row if it has none. Returns the tenant's row and whether it is new.
    fn put_record<'a>(
        &'a self,
        record: NewRecord<'a>,
    ) -> BoxFuture<'a, Result<(RecordRow, bool), StoreError>>;
    /// The tenant's record.
    fn get_record<'a>(
        &'a self,
        tenant: &'a str,
        id: &'a str,
    ) -> BoxFuture<'a, Result<Option<RecordRow>, StoreError>>;
    /// The samples (dt, m/s²) of the tenant's record.
    fn record_samples<'a>(
        &'a self,
        tenant: &'a str,
        id: &'a str,
    ) -> BoxFuture<'a, Result<Option<Samples>, StoreError>>;
    /// The tenant's records, newest first, uploaded before `before` if given.
    fn list_records<'a>(
        &'a self,
        tenant: &'a str,
        limit: u32,
        before: Option<Uuid>,
    ) -> BoxFuture<'a, Result<Vec<RecordRow>, StoreError>>;
    /// Deletes the tenant's record unless a live job of the tenant uses it.
    fn delete_record<'a>(
        &'a self,
        tenant: &'a str,
        id: &'a str,
    ) -> BoxFuture<'a, Result<RecordDeleted, StoreError>>;
}

const RECORD_SELECT: &str = "SELECT id, entry, name, meta, created_at FROM records ";

/// Samples as stored: f64, little-endian.
fn to_bytes(acc: &[f64]) -> Vec<u8> {
    acc.iter().flat_map(|a| a.to_le_bytes()).collect()
}

fn from_bytes(bytes: &[u8]) -> Result<Vec<f64>, StoreError> {
    if !bytes.len().is_multiple_of(8) {
        return Err(StoreError::Corrupt(format!(
            "record samples of {} bytes",
            bytes.len()
        )));
    }
    Ok(bytes
        .chunks_exact(8)
        .map(|c| {
            let mut b = [0u8; 8];
            b.copy_from_slice(c);
            f64::from_le_bytes(b)
        })
        .collect())
}

impl<DB> SqlStore<DB>
where
    DB: Dialect,
    DB::QueryResult: RowsAffected,
    for<'c> &'c mut DB::Connection: Executor<'c, Database = DB>,
    DB::Arguments: IntoArguments<DB>,
    String: Type<DB> + for<'q> Encode<'q, DB> + for<'r> Decode<'r, DB>,
    i64: Type<DB> + for<'q> Encode<'q, DB> + for<'r> Decode<'r, DB>,
    f64: Type<DB> + for<'q> Encode<'q, DB> + for<'r> Decode<'r, DB>,
    Option<String>: for<'q> Encode<'q, DB>,
    Option<i64>: for<'q> Encode<'q, DB>,
    Vec<u8>: Type<DB> + for<'q> Encode<'q, DB> + for<'r> Decode<'r, DB>,
    for<'n> &'n str: ColumnIndex<DB::Row>,
    usize: ColumnIndex<DB::Row>,
{
    fn record_row(row: &DB::Row) -> Result<RecordRow, StoreError> {
        Ok(RecordRow {
            id: row.try_get("id")?,
            entry: super::sql::parse_id(&row.try_get::<String, _>("entry")?)?,
            name: row.try_get("name")?,
            meta: row.try_get("meta")?,
            created_at: row.try_get("created_at")?,
        })
    }

    async fn record_in(
        conn: &mut DB::Connection,
        tenant: &str,
        id: &str,
    ) -> Result<Option<RecordRow>, StoreError> {
        let row = sqlx::query(AssertSqlSafe(format!(
            "{RECORD_SELECT}WHERE tenant = $1 AND id = $2"
        )))
        .bind(tenant.to_string())
        .bind(id.to_string())
        .fetch_optional(conn)
        .await?;
        row.as_ref().map(Self::record_row).transpose()
    }

    async fn put_in(
        &self,
        conn: &mut DB::Connection,
        new: NewRecord<'_>,
    ) -> Result<(RecordRow, bool), StoreError> {
        let mut tx = conn.begin().await?;
        if let Some(row) = Self::record_in(&mut tx, new.tenant, new.id).await? {
            return Ok((row, false));
        }
        sqlx::query(
            "INSERT INTO record_samples (id, dt, samples, acc) VALUES ($1, $2, $3, $4) \
             ON CONFLICT (id) DO NOTHING",
        )
        .bind(new.id.to_string())
        .bind(new.dt)
        .bind(new.acc.len() as i64)
        .bind(to_bytes(new.acc))
        .execute(&mut *tx)
        .await?;
        sqlx::query(
            "INSERT INTO records (entry, tenant, id, name, meta, created_at) VALUES ($1, $2, $3, $4, $5, $6)",
        )
        .bind(new.entry.to_string())
        .bind(new.tenant.to_string())
        .bind(new.id.to_string())
        .bind(new.name.to_string())
        .bind(new.meta.to_string())
        .bind(new.now.to_string())
        .execute(&mut *tx)
        .await?;
        let row = Self::record_in(&mut tx, new.tenant, new.id)
            .await?
            .ok_or_else(|| StoreError::Corrupt("stored record vanished".into()))?;
        tx.commit().await?;
        Ok((row, true))
    }

    async fn delete_record_in(
        &self,
        conn: &mut DB::Connection,
        tenant: &str,
        id: &str,
    ) -> Result<RecordDeleted, StoreError> {
        let mut tx = conn.begin().await?;
        // The record's row, locked: a submission naming it reads it first.
        let found = sqlx::query(AssertSqlSafe(fill::<DB>(
            "SELECT entry FROM records WHERE tenant = $1 AND id = $2{for_update}",
        )))
        .bind(tenant.to_string())
        .bind(id.to_string())
        .fetch_optional(&mut *tx)
        .await?;
        if found.is_none() {
            return Ok(RecordDeleted::NotFound);
        }
        let live: Vec<String> = sqlx::query_scalar(
            "SELECT j.id FROM job_records r JOIN jobs j ON j.id = r.job_id \
             WHERE r.record_id = $1 AND j.tenant = $2 AND j.status IN ('queued', 'running') \
             ORDER BY j.id LIMIT 20",
        )
        .bind(id.to_string())
        .bind(tenant.to_string())
        .fetch_all(&mut *tx)
        .await?;
        if !live.is_empty() {
            let ids = live
                .iter()
                .map(|j| super::sql::parse_id(j))
                .collect::<Result<Vec<_>, _>>()?;
            return Ok(RecordDeleted::InUse(ids));
        }
        sqlx::query("DELETE FROM records WHERE tenant = $1 AND id = $2")
            .bind(tenant.to_string())
            .bind(id.to_string())
            .execute(&mut *tx)
            .await?;
        sqlx::query(
            "DELETE FROM record_samples WHERE id = $1 \
             AND NOT EXISTS (SELECT 1 FROM records r WHERE r.id = record_samples.id)",
        )
        .bind(id.to_string())
        .execute(&mut *tx)
        .await?;
        tx.commit().await?;
        Ok(RecordDeleted::Gone)
    }
}

impl<DB> RecordStore for SqlStore<DB>
where
    DB: Dialect,
    DB::QueryResult: RowsAffected,
    for<'c> &'c mut DB::Connection: Executor<'c, Database = DB>,
    DB::Arguments: IntoArguments<DB>,
    String: Type<DB> + for<'q> Encode<'q, DB> + for<'r> Decode<'r, DB>,
    i64: Type<DB> + for<'q> Encode<'q, DB> + for<'r> Decode<'r, DB>,
    f64: Type<DB> + for<'q> Encode<'q, DB> + for<'r> Decode<'r, DB>,
    Option<String>: for<'q> Encode<'q, DB>,
    Option<i64>: for<'q> Encode<'q, DB>,
    Vec<u8>: Type<DB> + for<'q> Encode<'q, DB> + for<'r> Decode<'r, DB>,
    for<'n> &'n str: ColumnIndex<DB::Row>,
    usize: ColumnIndex<DB::Row>,
{
    fn put_record<'a>(
        &'a self,
        record: NewRecord<'a>,
    ) -> BoxFuture<'a, Result<(RecordRow, bool), StoreError>> {
        Box::pin(async move { in_write_turn!(self, |conn| self.put_in(conn, record)) })
    }

    fn get_record<'a>(
        &'a self,
        tenant: &'a str,
        id: &'a str,
    ) -> BoxFuture<'a, Result<Option<RecordRow>, StoreError>> {
        Box::pin(async move {
            let mut conn = self.pool().acquire().await?;
            Self::record_in(&mut conn, tenant, id).await
        })
    }

    fn record_samples<'a>(
        &'a self,
        tenant: &'a str,
        id: &'a str,
    ) -> BoxFuture<'a, Result<Option<Samples>, StoreError>> {
        Box::pin(async move {
            let row = sqlx::query(
                "SELECT s.dt, s.acc FROM record_samples s JOIN records r ON r.id = s.id \
                 WHERE r.tenant = $1 AND r.id = $2",
            )
            .bind(tenant.to_string())
            .bind(id.to_string())
            .fetch_optional(self.pool())
            .await?;
            match row {
                None => Ok(None),
                Some(r) => {
                    let dt: f64 = r.try_get("dt")?;
                    let bytes: Vec<u8> = r.try_get("acc")?;
                    Ok(Some((dt, from_bytes(&bytes)?)))
                }
            }
        })
    }

    fn list_records<'a>(
        &'a self,
        tenant: &'a str,
        limit: u32,
        before: Option<Uuid>,
    ) -> BoxFuture<'a, Result<Vec<RecordRow>, StoreError>> {
        Box::pin(async move {
            let rows = sqlx::query(AssertSqlSafe(format!(
                "{RECORD_SELECT}WHERE tenant = $1 AND ($2 IS NULL OR entry < $2) ORDER BY entry DESC LIMIT $3"
            )))
            .bind(tenant.to_string())
            .bind(before.map(|b| b.to_string()))
            .bind(i64::from(limit))
            .fetch_all(self.pool())
            .await?;
            rows.iter().map(Self::record_row).collect()
        })
    }

    fn delete_record<'a>(
        &'a self,
        tenant: &'a str,
        id: &'a str,
    ) -> BoxFuture<'a, Result<RecordDeleted, StoreError>> {
        Box::pin(
            async move { in_write_turn!(self, |conn| self.delete_record_in(conn, tenant, id)) },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_round_trip_bit_for_bit() {
        let acc = [0.0, -0.0, 1.0 / 3.0, -9.81e-300, f64::MAX];
        let back = from_bytes(&to_bytes(&acc)).expect("whole samples");
        assert_eq!(
            acc.map(f64::to_bits).to_vec(),
            back.iter().map(|a| a.to_bits()).collect::<Vec<_>>()
        );
        assert!(from_bytes(&[0u8; 12]).is_err());
    }
}
