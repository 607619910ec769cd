// The pressure sensor's spec (sensors/pressure_sensor.h; keys: PressureSensor::keys()).
#pragma once


namespace hadal::sensors {

struct PressureSensor;

struct PressureSpec {
  using Kind = PressureSensor;
  double noise_stddev = 0.0;  // white noise per sample [Pa]
  double resolution = 0.0;    // quantisation step [Pa]; 0: none
  double range_pa = 1.2e8;   // full scale, absolute [Pa]
  double offset = 0.0;        // added to every reading before quantisation and clipping [Pa]
};

}  // namespace hadal::sensors
