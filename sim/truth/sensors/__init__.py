"""Sensor models of the truth side: they turn the true state into what the
flight software is allowed to see, with noise drawn from the run's generator."""
