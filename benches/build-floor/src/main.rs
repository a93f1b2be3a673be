use polars::prelude::*;

fn main() -> PolarsResult<()> {
    let path = std::env::args().nth(1).expect("a Parquet file");
    let df = LazyFrame::scan_parquet(PlRefPath::new(path.as_str()), Default::default())?.select([col("n_stick").mean()]).collect()?;
    println!("{df}");
    Ok(())
}
