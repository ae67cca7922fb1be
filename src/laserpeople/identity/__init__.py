"""Identities of tracked people: colour appearance and re-identification after crossings
(002 Sec. 2)."""
