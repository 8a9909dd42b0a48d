#!/usr/bin/env bash
# The release step: tag the commit checked out as v<version>, the version in pyproject.toml.
# That tag is what a pre-commit `rev:` and `pip install 'motiontool @ git+URL@v<version>'` name
# (docs/ci.md); tests/test_ci_docs.py runs this script in a clone, then pre-commit at the tag.
# Run it on a clean checkout of the commit to release, once CHANGELOG.md names the version:
#     bash dev/release.sh        # then the git push it prints
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3}
version=$("$PY" -c 'import tomllib; print(tomllib.load(open("pyproject.toml", "rb"))["project"]["version"])')
tag="v$version"
if [ -n "$(git status --porcelain --untracked-files=no)" ]; then
    echo "release: the checkout has uncommitted changes; commit them first" >&2
    exit 2
fi
if git rev-parse -q --verify "refs/tags/$tag" >/dev/null; then
    echo "release: $tag exists already (commit $(git rev-parse --short "$tag^{commit}")); raise the version in pyproject.toml" >&2
    exit 2
fi
git tag "$tag"
echo "release: tagged $(git rev-parse --short HEAD) as $tag; publish it with: git push origin $tag"
