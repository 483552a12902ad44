"""Constants of composer, as dm_control names them (`composer.SENSOR_SITES_GROUP`)."""

# The MJCF site group in which entities put the sites their sensors are attached to, so
# that a viewer can show or hide them together.
SENSOR_SITES_GROUP = 4

__all__ = ["SENSOR_SITES_GROUP"]
