# Sourced by scripts/main.sh and scripts/test.sh (and .ci/run): go to the repo
# root, check the Rust toolchain, create/update the Python venv .venv from the
# pinned requirements.txt. Idempotent: pip runs only when requirements.txt changed.
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$REPO"
if ! command -v cargo >/dev/null 2>&1; then
    echo "error: cargo not found; install a Rust toolchain (rustup) first" >&2
    exit 1
fi
PYTHON_BOOT="${PYTHON:-python3}"
if [ ! -x .venv/bin/python ]; then
    echo "== creating Python venv .venv ($("$PYTHON_BOOT" --version))"
    "$PYTHON_BOOT" -m venv .venv
fi
_req_hash="$(sha256sum requirements.txt | cut -d' ' -f1)"
if [ ! -f .venv/.requirements.sha256 ] || [ "$(cat .venv/.requirements.sha256)" != "$_req_hash" ]; then
    echo "== pip install -r requirements.txt"
    .venv/bin/python -m pip install --quiet --disable-pip-version-check -r requirements.txt
    echo "$_req_hash" > .venv/.requirements.sha256
fi
# The study tool gearstudy/ (docs/studies.md), installed editable into the venv; redone when
# its metadata or the repository's place changes, or when it is not importable.
_gs_hash="$(cat gearstudy/pyproject.toml - <<<"$REPO" | sha256sum | cut -d' ' -f1)"
if [ ! -f .venv/.gearstudy.sha256 ] || [ "$(cat .venv/.gearstudy.sha256)" != "$_gs_hash" ] \
    || ! .venv/bin/python -c "import importlib.util, sys; sys.exit(importlib.util.find_spec('gearstudy') is None)"; then
    echo "== pip install -e gearstudy"
    .venv/bin/python -m pip install --quiet --disable-pip-version-check --no-deps -e gearstudy
    echo "$_gs_hash" > .venv/.gearstudy.sha256
fi
VPY="$REPO/.venv/bin/python"
export MPLBACKEND=Agg
