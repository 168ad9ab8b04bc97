# Sourced by the benchmark scripts that run AllanTools: the benchmark
# folders, and a virtual environment in bench/.venv holding AllanTools 2024.6,
# NumPy and pandas (made on first use, reused after).
bench_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(dirname "$bench_dir")"
venv="$bench_dir/.venv"
py="$venv/bin/python"
data_dir="$bench_dir/data"

ensure_allantools_venv() {
  if ! "$py" -c 'import allantools, numpy, pandas
assert allantools.__version__ in ("2024.6", "2024.06")' 2>/dev/null; then
    "${PYTHON:-python3}" -m venv "$venv"
    "$py" -m pip install --quiet --disable-pip-version-check allantools==2024.6 numpy pandas
  fi
}
