#!/usr/bin/env bash
# fird optimize across N nodes of G GPUs under Slurm: one rank per GPU, rank 0 runs the
# search and writes every output, the others trace their shares of each batch
# (docs/scale-out.md). Set N and G below (or on sbatch's command line: sbatch -N 4
# --ntasks-per-node 8 --gpus-per-node 8 ...).
#
#   sbatch scripts/slurm_search.sh SCENE OUT [fird optimize options...]
#
# A second submission with the same OUT continues the search recorded there (--resume), on
# any number of nodes: a job that ran out of time, lost a node or was preempted ends where an
# uninterrupted one would have.
#SBATCH --job-name=fird-search
#SBATCH --nodes=2
#SBATCH --ntasks-per-node=4
#SBATCH --gpus-per-node=4
#SBATCH --cpus-per-task=2
#SBATCH --time=04:00:00
#SBATCH --output=fird-search-%j.log
set -euo pipefail

scene=${1:?usage: sbatch scripts/slurm_search.sh SCENE OUT [fird optimize options...]}
out=${2:?usage: sbatch scripts/slurm_search.sh SCENE OUT [fird optimize options...]}
shift 2
fird=${FIRD:-fird}

# Each rank opens the GPU of its rank on the node (SLURM_LOCALID), modulo the GPUs it sees:
# with every GPU of the node visible it takes its own, with one bound to each task (Slurm's
# --gpus-per-task=1) it takes that one. The scene, the files it names and OUT must be on a
# file system every node reads (every rank reads the scene; rank 0 alone writes OUT).
# One core per rank is enough for the fast path on a GPU; lavapipe (no GPU) wants more.
if [[ -f "$out/options.json" ]]; then
  # The settings it began with are in OUT: options are refused with --resume.
  exec srun --mpi=pmix "$fird" optimize "$scene" --resume "$out"
fi
exec srun --mpi=pmix "$fird" optimize "$scene" --out "$out" "$@"
