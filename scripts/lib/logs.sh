# Sourced by scripts/real-logs.sh, scripts/ardupilot-sitl.sh and scripts/ab-patch.sh: the logs
# written by others that the repository commits (origin, licence and hash in each folder's
# README), run from the repository's root.
# shellcheck disable=SC2034
REAL_LOGS=(host-tests/cli/data/logs/real/*.ulg host-tests/cli/data/logs/esc_status_log.ulg
           host-tests/cli/data/logs/real/*.bin host-tests/cli/data/logs/real/*.px4log)
SITL_LOGS=(host-tests/cli/data/logs/ardupilot-sitl/*.bin)
