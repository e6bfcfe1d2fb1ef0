//! Reading and writing query files in the `CCDQ0001` format (described in the `ccd_queries`
//! module documentation).

use std::path::Path;

use super::{CcdQuery, QuerySource};
use crate::crosscheck::error::{CrosscheckError, QueryProblem};

/// The file's first 8 bytes.
pub const MAGIC: &[u8; 8] = b"CCDQ0001";
/// Bytes before the first query.
pub const HEADER_BYTES: usize = 16;
/// Bytes per query: the source code and 24 `f64`.
pub const QUERY_BYTES: usize = 1 + 24 * 8;

/// Writes `queries` to `path` in the `CCDQ0001` format (module documentation).
pub fn write_queries(path: &Path, queries: &[CcdQuery]) -> Result<(), CrosscheckError> {
    let mut bytes = Vec::with_capacity(HEADER_BYTES + QUERY_BYTES * queries.len());
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&(queries.len() as u64).to_le_bytes());
    for q in queries {
        bytes.push(q.source.code());
        for x in q.points.iter().flatten() {
            bytes.extend_from_slice(&x.to_le_bytes());
        }
    }
    std::fs::write(path, bytes).map_err(|e| problem(path, QueryProblem::Write(e.to_string())))
}

/// Reads a file written by [`write_queries`].
pub fn read_queries(path: &Path) -> Result<Vec<CcdQuery>, CrosscheckError> {
    let bytes =
        std::fs::read(path).map_err(|e| problem(path, QueryProblem::Read(e.to_string())))?;
    if bytes.len() < HEADER_BYTES {
        return Err(problem(
            path,
            QueryProblem::ShortHeader {
                bytes: bytes.len(),
                header: HEADER_BYTES,
            },
        ));
    }
    if &bytes[..8] != MAGIC {
        return Err(problem(
            path,
            QueryProblem::Magic {
                found: String::from_utf8_lossy(&bytes[..8]).into_owned(),
                expected: String::from_utf8_lossy(MAGIC).into_owned(),
            },
        ));
    }
    let count = u64::from_le_bytes(bytes[8..16].try_into().expect("8 bytes"));
    let expected = usize::try_from(count)
        .ok()
        .and_then(|c| c.checked_mul(QUERY_BYTES))
        .and_then(|b| b.checked_add(HEADER_BYTES));
    match expected {
        Some(e) if e == bytes.len() => {}
        Some(e) if e > bytes.len() => {
            return Err(problem(
                path,
                QueryProblem::Truncated {
                    count,
                    expected: e,
                    bytes: bytes.len(),
                },
            ))
        }
        Some(e) => {
            return Err(problem(
                path,
                QueryProblem::Trailing {
                    extra: bytes.len() - e,
                    count,
                },
            ))
        }
        None => return Err(problem(path, QueryProblem::Count(count))),
    }
    bytes[HEADER_BYTES..]
        .chunks_exact(QUERY_BYTES)
        .enumerate()
        .map(|(i, record)| {
            let source = QuerySource::from_code(record[0]).ok_or_else(|| {
                problem(
                    path,
                    QueryProblem::Source {
                        index: i,
                        code: record[0],
                    },
                )
            })?;
            let mut points = [[0.0; 3]; 8];
            for (k, chunk) in record[1..].chunks_exact(8).enumerate() {
                points[k / 3][k % 3] = f64::from_le_bytes(chunk.try_into().expect("8 bytes"));
            }
            Ok(CcdQuery { source, points })
        })
        .collect()
}

/// A problem of the query file `path`.
pub(crate) fn problem(path: &Path, problem: QueryProblem) -> CrosscheckError {
    CrosscheckError::Queries {
        file: path.display().to_string(),
        problem,
    }
}

#[cfg(test)]
mod tests {
    use super::super::random_queries;
    use super::*;

    fn temp(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("ccd-queries-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn queries_round_trip_bitwise_through_the_file() {
        let mut queries = random_queries(50, 7);
        queries[3].source = QuerySource::Sphere;
        queries[4].source = QuerySource::Beam;
        queries[5].points[2][1] = -0.0;
        queries[6].points[7][2] = f64::MIN_POSITIVE / 4.0;
        let path = temp("round-trip.ccdq");
        write_queries(&path, &queries).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(bytes.len(), 16 + 193 * 50);
        assert_eq!(&bytes[..8], b"CCDQ0001");
        assert_eq!(bytes[16 + 193 * 4], 1, "source code of query 4");
        let back = read_queries(&path).unwrap();
        assert_eq!(back.len(), queries.len());
        for (a, b) in queries.iter().zip(&back) {
            assert_eq!(a.source, b.source);
            assert_eq!(a.key(), b.key());
        }
        write_queries(&path, &[]).unwrap();
        assert!(read_queries(&path).unwrap().is_empty());
    }

    #[test]
    fn bad_magic_and_truncated_files_are_refused_naming_the_file() {
        let queries = random_queries(3, 1);
        let path = temp("broken.ccdq");
        write_queries(&path, &queries).unwrap();
        let good = std::fs::read(&path).unwrap();

        let mut bad = good.clone();
        bad[..8].copy_from_slice(b"CCDQ0002");
        std::fs::write(&path, &bad).unwrap();
        let e = read_queries(&path).unwrap_err().to_string();
        assert!(e.contains("broken.ccdq") && e.contains("bad magic"), "{e}");

        std::fs::write(&path, &good[..good.len() - 1]).unwrap();
        let e = read_queries(&path).unwrap_err().to_string();
        assert!(e.contains("broken.ccdq") && e.contains("truncated"), "{e}");

        std::fs::write(&path, &good[..10]).unwrap();
        let e = read_queries(&path).unwrap_err().to_string();
        assert!(e.contains("broken.ccdq") && e.contains("truncated"), "{e}");

        let mut extra = good.clone();
        extra.push(0);
        std::fs::write(&path, &extra).unwrap();
        let e = read_queries(&path).unwrap_err().to_string();
        assert!(
            e.contains("broken.ccdq") && e.contains("1 bytes after"),
            "{e}"
        );

        let mut unknown = good.clone();
        unknown[16] = 9;
        std::fs::write(&path, &unknown).unwrap();
        let e = read_queries(&path).unwrap_err().to_string();
        assert!(e.contains("unknown source code 9"), "{e}");

        let e = read_queries(&temp("missing.ccdq")).unwrap_err().to_string();
        assert!(
            e.contains("missing.ccdq") && e.contains("cannot read"),
            "{e}"
        );
    }
}
