"""Flight software: sees only SensorRecords and ground commands, produces only
ActuatorCommands. Never imports sim.truth."""
