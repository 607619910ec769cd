// The sensor kinds: the one list every layer dispatches over (sensors/sensor_kind.h has the contract a
// kind fulfils; docs/ARCHITECTURE.md walks through adding one). Adding a kind is its module and one
// entry here.
#pragma once

#include "hadal/core/kind_list.h"
#include "hadal/sensors/altimeter_sensor.h"
#include "hadal/sensors/camera_sensor.h"
#include "hadal/sensors/dvl_sensor.h"
#include "hadal/sensors/force_torque_sensor.h"
#include "hadal/sensors/fls_sensor.h"
#include "hadal/sensors/gps_sensor.h"
#include "hadal/sensors/imu_sensor.h"
#include "hadal/sensors/lbl_sensor.h"
#include "hadal/sensors/magnetometer_sensor.h"
#include "hadal/sensors/modem_sensor.h"
#include "hadal/sensors/multibeam_sensor.h"
#include "hadal/sensors/pressure_sensor.h"
#include "hadal/sensors/profiler_sensor.h"
#include "hadal/sensors/sensor_specs.h"
#include "hadal/sensors/sidescan_sensor.h"
#include "hadal/sensors/usbl_sensor.h"

#include <type_traits>

namespace hadal::sensors {

using SensorKinds =
    KindList<PressureSensor, ImuSensor, MagnetometerSensor, GpsSensor, DvlSensor, AltimeterSensor, ProfilerSensor,
             CameraSensor, FlsSensor, MultibeamSensor, SidescanSensor, ForceTorqueSensor, UsblSensor,
             LblSensor, ModemSensor>;

// The model's variant of specs (sensors/sensor_specs.h) is this list's.
static_assert(std::is_same_v<SensorKindSpec, SensorKinds::Specs>, "sensors/sensor_specs.h lists the kinds in this order");
using SensorKindState = SensorKinds::States;  // the matching State, same index

}  // namespace hadal::sensors
