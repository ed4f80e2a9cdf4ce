//! `hal.stream`: the FIFOs of sampler and streamer (and streams of their
//! own) from Python. A stream is identified by LinuxCNC's integer key;
//! `hal.streamer_base + n` is streamer channel n, `hal.sampler_base + n`
//! sampler channel n.

use std::sync::Mutex;

use hal_core::{HalType, RingReader, RingWriter};
use pyo3::exceptions::{PyOSError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyTuple};

use crate::codes;
use crate::component::PyComponent;
use crate::convert::{to_python, to_value};

/// An `OSError` with errno, as LinuxCNC raises for stream failures.
fn os_error(errno: i32) -> PyErr {
    let text = match errno {
        libc::ENOENT => "No such file or directory",
        libc::EEXIST => "File exists",
        libc::ENOSPC => "No space left on device",
        _ => "Invalid argument",
    };
    PyOSError::new_err((errno, text))
}

/// Both ends of the ring and the counters of this handle.
struct Ends {
    writer: RingWriter,
    reader: RingReader,
    /// Sample number of the last record read.
    sampleno: u32,
    /// Records this handle tried to write; each gets the next number.
    attempts: u64,
    underruns: i32,
    overruns: i32,
}

/// A HAL stream: a FIFO of records with typed columns between a realtime
/// function and a user-space program.
#[pyclass(frozen, name = "stream", module = "hal")]
pub(crate) struct PyStream {
    comp: Py<PyComponent>,
    key: i32,
    creator: bool,
    types: Vec<HalType>,
    ends: Mutex<Ends>,
}

fn parse_types(text: &str) -> PyResult<Vec<HalType>> {
    match hal_components::infra::columns::parse_cfg("hal.stream", text) {
        Ok(t) if !t.is_empty() => Ok(t),
        _ => Err(os_error(libc::EINVAL)),
    }
}

impl PyStream {
    /// Runs `f` on the ring while the component exists.
    fn with_ends<T>(
        &self,
        py: Python<'_>,
        f: impl FnOnce(&mut Ends) -> PyResult<T>,
    ) -> PyResult<T> {
        self.comp.bind(py).get().shared.with_component(|_| {
            let mut ends = self.ends.lock().unwrap_or_else(|e| e.into_inner());
            f(&mut ends)
        })
    }
}

#[pymethods]
impl PyStream {
    /// `stream(comp, key, depth, types)` creates a stream;
    /// `stream(comp, key[, types])` attaches to an existing one, checking
    /// its column types if given.
    #[new]
    #[pyo3(signature = (*args))]
    fn new(args: &Bound<'_, PyTuple>) -> PyResult<Self> {
        let n = args.len();
        if !(2..=4).contains(&n) {
            return Err(PyTypeError::new_err(format!(
                "hal.stream takes 2 to 4 arguments ({n} given)"
            )));
        }
        let comp = args.get_item(0)?.cast_into::<PyComponent>().map_err(|e| {
            PyTypeError::new_err(format!("hal.stream argument 1 must be hal.component: {e}"))
        })?;
        let key: i32 = args.get_item(1)?.extract()?;
        let (depth, types): (i32, Option<String>) = if n == 4 {
            (
                args.get_item(2)?.extract()?,
                Some(args.get_item(3)?.extract()?),
            )
        } else if n == 3 {
            (0, Some(args.get_item(2)?.extract()?))
        } else {
            (0, None)
        };
        let name = codes::stream_region(key);
        let shared = comp.get().shared.clone();
        let (writer, reader, types, creator) = shared.with_component(|c| {
            if depth != 0 {
                let types = parse_types(types.as_deref().unwrap_or(""))?;
                let depth = usize::try_from(depth).map_err(|_| os_error(libc::EINVAL))?;
                if c.instance().region(&name).is_ok() {
                    return Err(os_error(libc::EEXIST));
                }
                let writer = RingWriter::create_typed(c, &name, depth, &types)
                    .map_err(|_| os_error(libc::EINVAL))?;
                let reader =
                    RingReader::open(c.instance(), &name).map_err(|_| os_error(libc::EINVAL))?;
                Ok((writer, reader, types, true))
            } else {
                let reader =
                    RingReader::open(c.instance(), &name).map_err(|_| os_error(libc::ENOENT))?;
                let have = reader
                    .column_types()
                    .ok_or_else(|| os_error(libc::EINVAL))?;
                if let Some(want) = types.as_deref() {
                    if parse_types(want)? != have {
                        return Err(os_error(libc::EINVAL));
                    }
                }
                let writer =
                    RingWriter::open(c.instance(), &name).map_err(|_| os_error(libc::EINVAL))?;
                Ok((writer, reader, have, false))
            }
        })?;
        Ok(PyStream {
            comp: comp.unbind(),
            key,
            creator,
            types,
            ends: Mutex::new(Ends {
                writer,
                reader,
                sampleno: 0,
                attempts: 0,
                underruns: 0,
                overruns: 0,
            }),
        })
    }

    /// The oldest record as a tuple, or None (counting an underrun) if
    /// there is none.
    fn read<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyTuple>>> {
        let mut record = vec![0u64; self.types.len() + 1];
        let got = self.with_ends(py, |e| {
            if e.reader.pop(&mut record) {
                e.sampleno = record[0] as u32;
                Ok(true)
            } else {
                e.underruns = e.underruns.wrapping_add(1);
                Ok(false)
            }
        })?;
        if !got {
            return Ok(None);
        }
        let values = self
            .types
            .iter()
            .zip(&record[1..])
            .map(|(t, bits)| to_python(py, hal_core::Value::from_bits(*t, *bits)))
            .collect::<PyResult<Vec<_>>>()?;
        Ok(Some(PyTuple::new(py, values)?))
    }

    /// Appends a record given as a tuple with one value per column. A full
    /// stream counts an overrun and raises OSError.
    fn write(&self, py: Python<'_>, data: &Bound<'_, PyTuple>) -> PyResult<()> {
        let n = self.types.len();
        if data.len() > n {
            return Err(PyValueError::new_err("Too many elements to unpack"));
        }
        if data.len() < n {
            return Err(PyValueError::new_err("Too few elements to unpack"));
        }
        let mut record = vec![0u64; n + 1];
        for (i, t) in self.types.iter().enumerate() {
            record[i + 1] = to_value(&data.get_item(i)?, *t)?.to_bits();
        }
        self.with_ends(py, |e| {
            e.attempts += 1;
            record[0] = e.attempts;
            if e.writer.push(&record) {
                Ok(())
            } else {
                e.overruns = e.overruns.wrapping_add(1);
                Err(os_error(libc::ENOSPC))
            }
        })
    }

    /// Whether a record is waiting.
    #[getter]
    fn readable(&self, py: Python<'_>) -> PyResult<bool> {
        self.with_ends(py, |e| Ok(!e.reader.is_empty()))
    }

    /// Whether there is room for a record.
    #[getter]
    fn writable(&self, py: Python<'_>) -> PyResult<bool> {
        self.with_ends(py, |e| Ok(e.writer.len() < e.writer.capacity()))
    }

    /// Records waiting.
    #[getter]
    fn depth(&self, py: Python<'_>) -> PyResult<usize> {
        self.with_ends(py, |e| Ok(e.reader.len()))
    }

    /// The depth the stream was created with.
    #[getter]
    fn maxdepth(&self, py: Python<'_>) -> PyResult<usize> {
        self.with_ends(py, |e| Ok(e.writer.depth()))
    }

    /// Reads that found no record, through this handle.
    #[getter]
    fn num_underruns(&self, py: Python<'_>) -> PyResult<i32> {
        self.with_ends(py, |e| Ok(e.underruns))
    }

    /// Writes that found no room, through this handle.
    #[getter]
    fn num_overruns(&self, py: Python<'_>) -> PyResult<i32> {
        self.with_ends(py, |e| Ok(e.overruns))
    }

    /// The sample number of the last record read.
    #[getter]
    fn sampleno(&self) -> u32 {
        self.ends.lock().unwrap_or_else(|e| e.into_inner()).sampleno
    }

    /// The column types as letters (`b'bfsu'`).
    #[getter]
    fn element_types<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        let letters: Vec<u8> = self.types.iter().map(|t| codes::type_letter(*t)).collect();
        PyBytes::new(py, &letters)
    }

    fn __repr__(&self) -> String {
        let creator = if self.creator { " creator" } else { "" };
        format!("<stream 0x{:x}{creator}>", self.key)
    }
}
