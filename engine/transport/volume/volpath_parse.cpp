// volpath's own settings (volpath.h's VolPathSettings) from the <renderer> element.
#include "engine/core/params.h"
#include "volpath.h"

namespace foton {

void parse_volpath(const ParamSet& params, RenderSettings& settings) {
    static const EnumTable<TransmittanceEstimator> names{
        {{"exact", TransmittanceEstimator::Exact}, {"ratio", TransmittanceEstimator::Ratio}}};
    VolPathSettings own;
    static const EnumTable<FreeFlightSampling> flights{
        {{"analytic", FreeFlightSampling::Analytic}, {"delta", FreeFlightSampling::Delta}}};
    own.transmittance = params.choice("transmittance", names, own.transmittance);
    own.free_flight = params.choice("free_flight", flights, own.free_flight);
    static const EnumTable<FlightKernel> kernels{
        {{"simd", FlightKernel::Simd}, {"scalar", FlightKernel::Scalar}}};
    own.flight_kernel = params.choice("flight_kernel", kernels, own.flight_kernel);
    own.spectral = params.boolean("spectral", own.spectral);
    settings.own = own;
}

}  // namespace foton
