#!/usr/bin/env bash
# Runs the split render on the current kubectl context: render parts, wait, merge.
# Usage: deploy/kubernetes/run.sh   (edit the Job files for the scene and sample counts first)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
kubectl apply -f "$here/storage.yaml"
kubectl delete job caustic-render caustic-merge --ignore-not-found
kubectl apply -f "$here/indexed-job.yaml"
kubectl wait --for=condition=complete job/caustic-render --timeout=24h
kubectl apply -f "$here/merge-job.yaml"
kubectl wait --for=condition=complete job/caustic-merge --timeout=1h
kubectl logs job/caustic-merge
