//! Touches each crate so that none is left out of the build: the number of rows of a Parquet file
//! as polars and as the parquet crate read it.
use polars::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args().nth(1).ok_or("usage: build-floor FILE.parquet")?;
    let df = LazyFrame::scan_parquet(PlRefPath::new(path.as_str()), Default::default())?.select([len()]).collect()?;
    let reader = parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder::try_new(std::fs::File::open(&path)?)?;
    let rows = reader.metadata().file_metadata().num_rows();
    let schema: arrow_schema::SchemaRef = reader.schema().clone();
    let empty = arrow_array::RecordBatch::new_empty(schema);
    println!("{df}\nparquet: {rows} rows, {} columns; {} bytes of buffers", empty.num_columns(), arrow_buffer::Buffer::from_vec(vec![0u8; 0]).len());
    Ok(())
}
