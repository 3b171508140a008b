#!/usr/bin/env bash
# The README's main-job command, exactly as the README writes it (scripts/readme_command.py reads
# it from the block marked `<!-- ci: main-job -->`), in a fresh venv, from the repository root;
# then the files it must have written. Step 3 of scripts/new-user-check.sh; .ci/run runs it on its
# own, while the portable wheel builds.
set -euo pipefail
cd "$(dirname "$0")/.."
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
printf '\n== new user: %s\n' "the README's main job, exactly as written, in a fresh venv"
main_job=$(python3 scripts/readme_command.py main-job)
echo "\$ $main_job"
python3 -m venv "$work/readme"
"$work/readme/bin/pip" install --quiet --upgrade pip
start=$(date +%s)
# The README's command runs with the venv first on PATH, as after `source venv/bin/activate`.
( export VIRTUAL_ENV="$work/readme" PATH="$work/readme/bin:$PATH"; bash -euo pipefail -c "$main_job" )
echo "README main job took $(( $(date +%s) - start )) s (including the build)"
for f in spatial6_computed_torque.png spatial6_torque_free.png spatial6_computed_torque.gif spatial6_computed_torque.npz; do
    test -s "spacearm-demo/$f" || { echo "the main job did not write spacearm-demo/$f" >&2; exit 1; }
done
